#!/usr/bin/env python3
"""tests/test_placement.py - the placement gate (tools/check/placement.py)
on hand-made sources and a hand-made ISR-path map: the markers read from
the definitions, a function of the ISR path without one failing, a
directory in RAM whole needing none, and a function a marked function of
the same file calls failing when it carries no marker itself. `make check` runs
the gate on the tree (tools/check/isr_path.sh). Standard library only."""
import os
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools", "check"))
import placement  # noqa: E402

SRC = """/* a comment naming RAMFUNC void fake(void) { } */
#include "x.h"

FLASHFUNC static float helper(float x)
{
    return 2.0f * x;
}

RAMFUNC static float ram_helper(float x)
{
    return x + 1.0f;
}

RAMFUNC void isr_part(int n,
                      void (*cb)(void))
{
    if (n > 0) {
        cb();
    }
    (void)ram_helper(1.0f);
}

FLASHFUNC uint16_t start_part(const char *s)
{
    return (uint16_t)helper((float)s[0]);
}

void background(void)
{
    isr_part(0, background);
}
"""


def map_of(entries):
    """ld's map with -ffunction-sections: (function, object) per input section."""
    lines = ["Memory Configuration", "", "Linker script and memory map", ""]
    for fn, obj in entries:
        lines.append(" .text.%s" % fn)
        lines.append("                0x0000000000000000       0x10 %s" % obj)
    return "\n".join(lines) + "\n"


class Placement(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.cwd = os.getcwd()
        os.chdir(self.dir.name)
        os.makedirs("firmware/app")
        os.makedirs("control")
        with open("firmware/app/part.c", "w") as f:
            f.write(SRC)
        with open("control/core.c", "w") as f:
            f.write("void core_step(void)\n{\n}\n")
        with open("target.mk", "w") as f:
            f.write("RAMFUNC_ALL := control\n")
        self.srcs = ["control/core.c", "firmware/app/part.c"]

    def tearDown(self):
        os.chdir(self.cwd)
        self.dir.cleanup()

    def check(self, entries):
        with open("isr.map", "w") as f:
            f.write(map_of(entries))
        return placement.check("isr.map", "target.mk", self.srcs)

    def test_markers_read_from_the_definitions(self):
        fns = placement.functions("firmware/app/part.c")
        self.assertEqual(sorted(fns), ["background", "helper", "isr_part", "ram_helper", "start_part"])
        self.assertEqual({n: m for n, (m, _s, _c) in fns.items()},
                         {"helper": "FLASHFUNC", "ram_helper": "RAMFUNC", "isr_part": "RAMFUNC",
                          "start_part": "FLASHFUNC", "background": None})
        self.assertTrue(fns["ram_helper"][1])
        self.assertFalse(fns["isr_part"][1])
        self.assertEqual(fns["isr_part"][2], {"cb", "ram_helper"})
        self.assertEqual(placement.ram_functions("firmware/app/part.c"), {"ram_helper", "isr_part"})

    def test_marked_and_ram_whole_functions_pass(self):
        obj = "build/check/isr/firmware_app_part.c.o"
        self.assertEqual(self.check([("isr_part", obj), ("start_part", obj), ("ram_helper.isra.0", obj),
                                     ("core_step", "build/check/isr/control_core.c.o")]), [])

    def test_an_excepted_file_of_a_ram_whole_directory_needs_markers(self):
        with open("target.mk", "a") as f:
            f.write("RAMFUNC_ALL_EXCEPT := control/core.c\n")
        self.assertFalse(placement.in_ram_whole("control/core.c", "target.mk"))
        fails = self.check([("core_step", "build/check/isr/control_core.c.o")])
        self.assertEqual(len(fails), 1)
        self.assertIn("control/core.c: core_step is on the ISR path without RAMFUNC", fails[0])

    def test_unmarked_function_on_the_isr_path_fails(self):
        fails = self.check([("background", "build/check/isr/firmware_app_part.c.o")])
        self.assertEqual(len(fails), 1)
        self.assertIn("firmware/app/part.c: background is on the ISR path without RAMFUNC", fails[0])

    def check_edited(self, old, new):
        """The gate on part.c with old replaced by new, no function on the map."""
        with open("firmware/app/part.c", "w") as f:
            f.write(SRC.replace(old, new))
        return self.check([])

    def test_unmarked_static_callee_of_a_ramfunc_fails(self):
        fails = self.check_edited("RAMFUNC static float ram_helper", "static float ram_helper")
        self.assertEqual(len(fails), 1)
        self.assertIn("ram_helper, called by RAMFUNC isr_part, is neither RAMFUNC nor FLASHFUNC", fails[0])

    def test_a_ramfunc_may_call_a_flashfunc(self):
        self.assertEqual(self.check_edited("RAMFUNC static float ram_helper", "FLASHFUNC static float ram_helper"), [])

    def test_unmarked_static_callee_of_a_flashfunc_fails(self):
        fails = self.check_edited("FLASHFUNC static float helper", "static float helper")
        self.assertEqual(len(fails), 1)
        self.assertIn("helper, called by FLASHFUNC start_part, is neither RAMFUNC nor FLASHFUNC", fails[0])

    def test_object_names_map_back_to_their_sources(self):
        self.assertEqual(placement.source_of("build/check/isr/firmware_app_part.c.o", self.srcs),
                         "firmware/app/part.c")
        self.assertIsNone(placement.source_of("build/check/isr/tests_fake.c.o", self.srcs))


if __name__ == "__main__":
    unittest.main()
