#!/usr/bin/env python3
"""tests/test_ram_budget.py - the RAM gate's parts (tools/check/ram_budget.py)
on hand-made inputs: the linker command file's ranges and placements, a
drive.map's MEMORY CONFIGURATION, the DATA_SECTION pragmas of a source
and where their sections go, and the Thumb-2 -> C28x word mapping, one
instruction class at a time with the words worked out by hand from the
rules in the script's header. `make check` runs the gate end to end (and
on a shrunk copy of the .cmd, which must fail). Standard library only."""
import os
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools", "check"))
import ram_budget  # noqa: E402

CMD = """
MEMORY
{
PAGE 0 :
   /* a comment with RAMX : origin = 0x1, length = 0x1 in it */
   RAMA  : origin = 0x008000, length = 0x001000
   FLASH : origin = 0x300000, length = 0x010000
PAGE 1 :
   RAMB  : origin = 0x000400, length = 0x000400
   RAMC  : origin = 0x00E000, length = 0x002000
}
SECTIONS
{
   .text : > FLASH, PAGE = 0
   ramfuncs : { *(ramfuncs) }
              LOAD = FLASH,
              RUN = RAMA,
              PAGE = 0
   .stack : > RAMB, PAGE = 1
   .ebss  : > RAMC, PAGE = 1,
            RUN_START(_EbssRunStart)
}
"""

MAP = """
MEMORY CONFIGURATION

         name            origin    length      used     unused   attr    fill
----------------------  --------  ---------  --------  --------  ----  --------
PAGE 0:
  RAMA                  00008000   00001000   00000f00  00000100  RWIX
  FLASH                 00300000   00010000   00001234  0000edcc  RWIX

PAGE 1:
  RAMC                  0000e000   00002000   00000200  00001e00  RWIX


SECTION ALLOCATION MAP
  RAMZ                  00000000   00000010   00000010  00000000  RWIX
"""


class CmdFile(unittest.TestCase):
    def test_ranges_and_placement(self):
        ranges, place = ram_budget.parse_cmd(CMD)
        self.assertEqual(ranges["RAMA"], (0, 0x8000, 0x1000))
        self.assertEqual(ranges["RAMC"], (1, 0xE000, 0x2000))
        self.assertNotIn("RAMX", ranges)  # comments are not ranges
        self.assertEqual(place, {"ramfuncs": "RAMA", ".stack": "RAMB", ".ebss": "RAMC"})

    def test_the_real_file(self):
        with open(os.path.join(ROOT, "firmware", "f28335", "f28335_flash.cmd")) as f:
            ranges, place = ram_budget.parse_cmd(f.read(), ["m0data"])
        self.assertEqual(ranges["RAML0L5"][1:], (0x8000, 0x5F80))
        self.assertEqual(place["ramfuncs"], "RAML0L5")
        self.assertEqual(place[".ebss"], "RAML5L7")
        self.assertEqual(place[".stack"], "RAMM1")
        self.assertEqual(place["m0data"], "RAMM0")   # main.c's DATA_SECTION objects

    def test_a_data_section_goes_where_the_file_places_it(self):
        cmd = CMD.replace("   .stack : > RAMB, PAGE = 1", "   .stack : > RAMB, PAGE = 1\n   mydata : > RAMC, PAGE = 1")
        _ranges, place = ram_budget.parse_cmd(cmd, ["mydata"])
        self.assertEqual(place["mydata"], "RAMC")
        with self.assertRaises(SystemExit) as e:    # a pragma's section the file does not place
            ram_budget.parse_cmd(CMD, ["mydata"])
        self.assertEqual(e.exception.code, 2)

    def test_the_pragmas_of_a_source(self):
        with tempfile.NamedTemporaryFile("w", suffix=".c", delete=False) as f:
            f.write('#pragma DATA_SECTION(g_a, "m0data")\nstatic int g_a;\n'
                    '#pragma  DATA_SECTION( g_b ,"m0data" )\nstatic int g_b;\n')
        try:
            self.assertEqual(ram_budget.data_sections([f.name]), {"m0data": [("g_a", f.name), ("g_b", f.name)]})
        finally:
            os.unlink(f.name)

    def test_a_union_holds_ramfuncs_and_the_flash_api(self):
        cmd = CMD.replace("""   ramfuncs : { *(ramfuncs) }
              LOAD = FLASH,
              RUN = RAMA,
              PAGE = 0""", """   UNION run = RAMA, PAGE = 0
   {
      ramfuncs : { *(ramfuncs) *(nvfuncs) } LOAD = FLASH, PAGE = 0
      Flash28_API : { Flash28335_API_V210.lib(.text) } LOAD = FLASH, PAGE = 0
   }""")
        _ranges, place = ram_budget.parse_cmd(cmd)
        self.assertEqual(place["ramfuncs"], "RAMA")
        self.assertEqual(place["Flash28_API"], "RAMA")
        # the overlay: the API must end before nvfuncs, the code that runs while it is there
        est = {"code_words": 4000, "nv_words": 100}
        line, failed = ram_budget.api_overlay_line(est, place)
        self.assertFalse(failed)
        est = {"code_words": ram_budget.FLASH_API_WORDS - ram_budget.FASTRTS_WORDS + 99, "nv_words": 100}
        line, failed = ram_budget.api_overlay_line(est, place)
        self.assertTrue(failed, line)
        self.assertIsNone(ram_budget.api_overlay_line(est, {"ramfuncs": "RAMA"}))

    def test_a_section_in_an_undefined_range_is_an_error(self):
        with self.assertRaises(SystemExit) as e:
            ram_budget.parse_cmd(CMD.replace("RUN = RAMA", "RUN = RAMQ"))
        self.assertEqual(e.exception.code, 2)


class DriveMap(unittest.TestCase):
    def test_used_words_of_memory_configuration_only(self):
        with tempfile.NamedTemporaryFile("w", suffix=".map", delete=False) as f:
            f.write(MAP)
        try:
            used = ram_budget.parse_map(f.name)
        finally:
            os.unlink(f.name)
        self.assertEqual(used, {"RAMA": 0xF00, "FLASH": 0x1234, "RAMC": 0x200})


class Words(unittest.TestCase):
    def w(self, hexes, mnem, ops=""):
        return ram_budget.c28x_words(hexes.split(), mnem, ops)

    def test_plain_instructions(self):
        self.assertEqual(self.w("4b02", "ldr", "r3, [pc, #8]"), 1)   # 16-bit
        self.assertEqual(self.w("f8d3 3004", "ldr.w", "r3, [r3, #4]"), 2)  # 32-bit
        self.assertEqual(self.w("00000000", ".word", "0x00000000"), 2)  # literal pool

    def test_offsets_beyond_three_bits(self):
        self.assertEqual(self.w("6a99", "ldr", "r1, [r3, #40]"), 2)  # 1 + ADDB
        self.assertEqual(self.w("ed93 7a0a", "vldr", "s14, [r3, #40]"), 3)
        self.assertEqual(self.w("ed93 7a07", "vldr", "s14, [r3, #28]"), 2)  # 7 words: in range

    def test_fpu(self):
        self.assertEqual(self.w("ee27 7a26", "vmul.f32", "s14, s14, s13"), 3)  # 2p: delay slot
        self.assertEqual(self.w("ee37 7a26", "vadd.f32", "s14, s14, s13"), 3)
        self.assertEqual(self.w("eeb8 7a67", "vcvt.f32.u32", "s14, s15"), 3)
        self.assertEqual(self.w("eeb0 7ac7", "vabs.f32", "s14, s14"), 2)   # single cycle
        self.assertEqual(self.w("eef1 fa10", "vmrs", "APSR_nzcv, fpscr"), 2)
        self.assertEqual(self.w("ee87 7a26", "vdiv.f32", "s14, s14, s13"), 4)  # FS$$DIV call

    def test_register_lists(self):
        self.assertEqual(self.w("b530", "push", "{r4, r5, lr}"), 3)
        self.assertEqual(self.w("e8bd 81f0", "pop.w", "{r4, r5, r6, r7, r8, pc}"), 6)
        self.assertEqual(self.w("cc0f", "ldmia", "r4!, {r0, r1, r2, r3}"), 4)
        self.assertEqual(self.w("ed2d 8b04", "vpush", "{d8-d9}"), 8)  # 4 S registers x 2
        self.assertEqual(self.w("ecbd 8a02", "vpop", "{s16-s17}"), 4)


if __name__ == "__main__":
    unittest.main()
