#!/usr/bin/env python3
"""ram_budget.py - the RAM gate of `make check`: what the F28335 image puts
in each RAM range of firmware/f28335/f28335_flash.cmd, the margin left, and a
failure when a margin is under MARGIN_MIN.

Usage: ram_budget.py --cmd F28335_CMD --objdir DIR [--map DRIVE_MAP] [--mk TARGET_MK] [--out FILE]

The RAM ranges and what goes in them are read from the linker command
file (MEMORY: name, origin, length in 16-bit words; SECTIONS: `ramfuncs`
RUN = range, or `UNION run = range` holding it, `.ebss`, `.stack`, `.esysmem` > range, and every section a
source names in `#pragma DATA_SECTION(object, "section")` > range: that
object counted there, not in .ebss). The figures are the
target's, from the first source available:

1. drive.map of a cl2000 build (`make firmware`), when present: the
   linker's own `used` column of MEMORY CONFIGURATION for every range.
2. Otherwise host estimates from the objects tools/check/isr_path.sh
   builds (arm-none-eabi-gcc -O2 for an ARMv7-A with FPU, Thumb-2,
   -ffunction-sections), converted to C28x 16-bit words:

   code (ramfuncs): every instruction of the functions placed in RAM
   (all of the directories in target.mk's RAMFUNC_ALL but its
   RAMFUNC_ALL_EXCEPT files, elsewhere the ones marked RAMFUNC or placed
   by a CODE_SECTION pragma in nvfuncs, the end of ramfuncs:
   tools/check/placement.py) is mapped to the C28x
   instruction(s) doing the same, sized from the opcode tables of the
   C28x CPU (SPRU430, 16- and 32-bit opcodes) and of its FPU (SPRUEO2, all
   FPU instructions 32-bit; the 2p-cycle ones, MPYF32/ADDF32/SUBF32/
   MACF32/conversions, need one delay slot before their result is read,
   counted as a NOP word, as if cl2000 filled none):
     16-bit Thumb instruction                     1 word
     32-bit Thumb instruction                     2 words
     VFP instruction (vldr, vstr, vmov, vcmp, vmrs, vabs, vneg ...)  2 words
     VFP multiply/add/subtract/MAC/convert        2 words + 1 delay-slot word
     vdiv, vsqrt (FS$$DIV, sqrtf calls)           4 words (LCR + operand move)
     push/pop, ldm/stm                            1 word per register (MOVL)
     vpush/vpop, vldm/vstm                        2 words per S register (MOV32)
     load/store with an offset beyond the C28x's 3-bit indirect offset
       (*+XARn[0..7], 8 words = 32 bytes)        +1 word (ADDB XARn,#7bit)
     literal pool word (.word)                    2 words
   The words over Thumb-2 bytes / 2 is the factor printed: derived from
   this build's own instruction mix, not a typed constant. Not modelled:
   the extra spill code of the C28x's fewer registers (8 FPU result
   registers against ARM's 32), which the unfilled delay slots counted
   above partly cover; the first drive.map replaces the estimate. Plus the FPU
   fast-RTS members linked into ramfuncs (sin/cos, atan2, sqrt, division):
   C2000Ware's libraries/math/FPUfastRTS/c28/source/fpu32/*_f32.asm hold
   49 + 16 + 43 + 21 = 129 instructions (counted there), at most 2 words
   each (no C28x instruction is longer): FASTRTS_WORDS. A UNION that
   holds ramfuncs and TI's flash API (Flash28_API: f28335_flash.cmd, run
   over ramfuncs' start while the parameter store writes) takes the larger
   of the two, and the API must end before nvfuncs, which runs while it
   is there: the RAM code before nvfuncs at least FLASH_API_WORDS, else
   the gate fails. FLASH_API_WORDS bounds the API: Flash28335_API_V210's
   .text 0x5A9 + .econst 0x48 = 1521 words, from a public listing of the
   library linked to run in RAM, rounded up to 0x600; the first drive.map
   gives the linker's own.
   data (.ebss): the .bss/.data/COMMON bytes of the image's objects
   built again with bool as a 16-bit type, at one word per two bytes. An
   upper bound: the portable sources have no 8-bit type (c28x_portable.h
   poisons them), so with bool widened every scalar is 16 bits or more,
   which takes half as many words on the C28x as bytes on ARM (an enum:
   4 bytes on ARM, 1 word on the C28x: over), and ARM's alignment in bytes
   is never below twice the C28x's in words. A file defining a writable
   char object (one word per character on the C28x) is counted at one
   word per byte instead. Plus RTS_EBSS_WORDS for the RTS library's own
   variables (errno, the exit and lock pointers: about 10 words in TI's
   F2833x example maps).
   stack (.stack): the range holds the whole --stack_size of target.mk
   (its margin there is the range's); what is judged is the need against
   that reserve: the larger of main's start-up chain (before
   hal_isr_attach: no interrupt yet) and main's frame + the deepest call
   of its loop + the deepest chain of ctrl_isr on top of it (a call of the
   loop between hal_isr_pause() and hal_isr_resume() runs with the ISR held
   off: counted as start-up is), from gcc's
   -fcallgraph-info=su frame sizes at one word per byte (twice what the
   same frame holds in C28x words: room for the extra spills of the C28x's
   fewer registers, an estimate, not a bound), plus ISR_CONTEXT_WORDS: the CPU's automatic context
   save (14 words, SPRU430 "Interrupts") and the interrupt prologue's save
   of the CPU and FPU save-on-call registers (at most 19 32-bit registers,
   38 words).

The gate fails (exit 1) when a range's margin (free / length, or for the
stack unused reserve / reserve) is under MARGIN_MIN, or when a file cannot
be read or parsed (exit 2). A drive.map overrides the estimates of the
ranges it lists.
"""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

import placement

MARGIN_MIN = 0.10
FASTRTS_WORDS = 2 * (49 + 16 + 43 + 21)
FLASH_API_WORDS = 0x600
RTS_EBSS_WORDS = 64
ISR_CONTEXT_WORDS = 14 + 2 * 19
C28X_INDIRECT_OFFSET_MAX_BYTES = 7 * 4  # *+XARn[3-bit] word offset of a 32-bit access, in ARM bytes

# VFP operations that are 2p-cycle on the C28x FPU (SPRUEO2): one delay slot.
FPU_2P = re.compile(r'^v(n?mul|add|sub|n?ml[as]|f[n]?m[as]|cvt)')
FPU_CALL = re.compile(r'^v(div|sqrt)')


def die(msg):
    print("ram_budget: error: " + msg)
    sys.exit(2)


def read(path):
    try:
        with open(path) as f:
            return f.read()
    except OSError as e:
        die("cannot read %s: %s" % (path, e.strerror))


def parse_cmd(text, data_sections=()):
    """MEMORY ranges {name: (page, origin, length)} and where the RAM sections go
    (with the DATA_SECTION sections named in data_sections)."""
    text = re.sub(r'/\*.*?\*/', '', text, flags=re.S)
    mem = re.search(r'MEMORY\s*\{(.*?)\n\}', text, re.S)
    sec = re.search(r'SECTIONS\s*\{(.*)\}', text, re.S)
    if not mem or not sec:
        die("no MEMORY or SECTIONS block in the linker command file")
    ranges, page = {}, None
    for line in mem.group(1).splitlines():
        m = re.match(r'\s*PAGE\s*(\d+)\s*:', line)
        if m:
            page = int(m.group(1))
            continue
        m = re.match(r'\s*(\w+)\s*:\s*origin\s*=\s*(0x[0-9A-Fa-f]+)\s*,\s*length\s*=\s*(0x[0-9A-Fa-f]+)', line)
        if m:
            ranges[m.group(1)] = (page, int(m.group(2), 16), int(m.group(3), 16))
    place = {}
    body = sec.group(1)
    union = union_block(body)
    if union is not None and re.search(r'\bramfuncs\s*:', union[1]):
        place['ramfuncs'] = union[0]
        if re.search(r'\bFlash28_API\s*:', union[1]):
            place['Flash28_API'] = union[0]
    else:
        m = re.search(r'\bramfuncs\s*:.*?\bRUN\s*=\s*(\w+)', body, re.S)
        if m:
            place['ramfuncs'] = m.group(1)
    for name in ('.ebss', '.stack', '.esysmem') + tuple(data_sections):
        m = re.search(r'(?m)^\s*' + re.escape(name) + r'\s*:\s*>\s*(\w+)', body)
        if m:
            place[name] = m.group(1)
        elif name in data_sections:
            die("a source places an object in section %s, which the linker command file does not place" % name)
    for name, rng in place.items():
        if rng not in ranges:
            die("section %s placed in %s, which MEMORY does not define" % (name, rng))
    for name in ('ramfuncs', '.ebss', '.stack'):
        if name not in place:
            die("the linker command file does not place %s" % name)
    return ranges, place


def union_block(body):
    """(run range, text) of the first `UNION run = RANGE ... { ... }` in SECTIONS, or None."""
    m = re.search(r'\bUNION\s+run\s*=\s*(\w+)[^{]*\{', body, re.I)
    if not m:
        return None
    depth, at = 1, m.end()
    while depth and at < len(body):
        depth += {'{': 1, '}': -1}.get(body[at], 0)
        at += 1
    return m.group(1), body[m.end():at - 1]


def parse_map(path):
    """drive.map: MEMORY CONFIGURATION {name: used words}."""
    used, on = {}, False
    for line in read(path).splitlines():
        if 'MEMORY CONFIGURATION' in line:
            on = True
            continue
        if on and 'SECTION ALLOCATION MAP' in line:
            break
        m = re.match(r'\s+(\w+)\s+([0-9a-fA-F]{8})\s+([0-9a-fA-F]{8})\s+([0-9a-fA-F]{8})\s+([0-9a-fA-F]{8})', line)
        if on and m:
            used[m.group(1)] = int(m.group(4), 16)
    if not used:
        die("%s has no MEMORY CONFIGURATION table" % path)
    return used


def obj_source(obj):
    """build/check/isr/control_ctrl_ctrl.c.o -> control/ctrl/ctrl.c (None: the register fake)"""
    src = placement.source_of(obj, placement.image_sources())
    return None if src is None or src.startswith('tests/') else src


def regcount(operands):
    m = re.search(r'\{([^}]*)\}', operands)
    if not m:
        return 1
    n = 0
    for part in m.group(1).split(','):
        part = part.strip()
        r = re.match(r'([a-z]+)(\d+)-[a-z]+(\d+)', part)
        n += (int(r.group(3)) - int(r.group(2)) + 1) if r else 1
    return n


def c28x_words(hexes, mnem, ops):
    """One disassembled Thumb-2 line -> estimated C28x words (see the header)."""
    if mnem in ('.word', '.short', '.byte'):
        return {'.word': 2, '.short': 1, '.byte': 1}[mnem]
    if mnem.startswith('vpush') or mnem.startswith('vpop') or re.match(r'^v(ld|st)m', mnem):
        regs = regcount(ops)
        return 2 * regs * (2 if re.search(r'\{\s*d', ops) else 1)
    if re.match(r'^(push|pop|ldm|stm)', mnem):
        return regcount(ops)
    if FPU_CALL.match(mnem):
        return 4
    words = 2 if len(hexes) == 2 or len(hexes[0]) == 8 or mnem.startswith('v') else 1
    if mnem.startswith('v') and FPU_2P.match(mnem):
        words += 1
    m = re.search(r'\[\w+,\s*#(-?\d+)\]', ops)
    if m and abs(int(m.group(1))) > C28X_INDIRECT_OFFSET_MAX_BYTES and 'pc' not in ops:
        words += 1
    return words


def disassemble(obj):
    """{function: (thumb_bytes, c28x_words)} of one object."""
    out = subprocess.run(['arm-none-eabi-objdump', '-d', obj], capture_output=True, text=True)
    if out.returncode != 0:
        die("objdump failed on %s: %s" % (obj, out.stderr.strip()))
    funcs, fn = {}, None
    for line in out.stdout.splitlines():
        m = re.match(r'^[0-9a-f]+ <([^>]+)>:$', line)
        if m:
            fn = m.group(1).split('.')[0]
            funcs.setdefault(fn, [0, 0])
            continue
        parts = line.split('\t')
        if fn is None or len(parts) < 3 or not re.match(r'^\s*[0-9a-f]+:$', parts[0]):
            continue
        hexes = parts[1].split()
        mnem = parts[2].strip().split(' ')[0] if parts[2].strip() else ''
        ops = parts[3] if len(parts) > 3 else ''
        if not hexes or not mnem:
            continue
        funcs[fn][0] += sum(len(h) // 2 for h in hexes)
        funcs[fn][1] += c28x_words(hexes, mnem, ops)
    return funcs


def data_bytes(obj):
    out = subprocess.run(['arm-none-eabi-size', '-A', obj], capture_output=True, text=True)
    if out.returncode != 0:
        die("size failed on %s" % obj)
    total = 0
    for line in out.stdout.splitlines():
        f = line.split()
        if len(f) >= 2 and re.match(r'^\.(bss|data|sbss|sdata)(\.|$)|^COMMON$', f[0]):
            total += int(f[1])
    # tentative definitions (COMMON) are symbols, not sections, in an object
    nm = subprocess.run(['arm-none-eabi-nm', '-S', obj], capture_output=True, text=True).stdout
    for line in nm.splitlines():
        f = line.split()
        if len(f) == 4 and f[2] in ('C',):
            total += int(f[1], 16)
    return total


# isr_path.sh's flags for the ARM build, and bool widened to 16 bits
# (stdbool.h's guard set first, so that it does not define bool as _Bool).
WIDE_BOOL_FLAGS = ['-mthumb', '-march=armv7-a+fp', '-mfloat-abi=hard', '-O2', '-std=c99', '-fdata-sections',
                   '-include', 'control/c28x_portable.h', '-D_STDBOOL_H', '-Dbool=uint16_t', '-Dtrue=1',
                   '-Dfalse=0', '-D__bool_true_false_are_defined=1', '-Ihal',
                   '-Ihal/f28335', '-Itests/c2000_fake/include']


def wide_bool_flags():
    """WIDE_BOOL_FLAGS, control/'s rooms and every room of firmware/ (layers.sh gates their order)."""
    rooms = re.search(r'(?m)^CONTROL_ROOMS\s*:=\s*(.*)$', open('control/rooms.mk').read()).group(1).split()
    return WIDE_BOOL_FLAGS + ['-I' + d for d in rooms] + ['-I' + d.rstrip('/') for d in sorted(glob.glob('firmware/*/'))]


CHAR_OBJECT = re.compile(r'(?m)^\s*(static\s+)?(volatile\s+)?(unsigned\s+|signed\s+)?char\s+\w+\s*\[')


DATA_SECTION = re.compile(r'#pragma\s+DATA_SECTION\s*\(\s*(\w+)\s*,\s*"(\w+)"\s*\)')


def data_sections(srcs):
    """{section: [(object, source)]} of the image's DATA_SECTION pragmas."""
    out = {}
    for src in srcs:
        for obj, sec in DATA_SECTION.findall(read(src)):
            out.setdefault(sec, []).append((obj, src))
    return out


def symbol_words(src, sym, tmpdir):
    """The C28x words of src's object sym: its size with bool widened, at one word per 2 B."""
    wide = os.path.join(tmpdir, 'sym_' + os.path.basename(src) + '.o')
    out = subprocess.run(['arm-none-eabi-gcc'] + wide_bool_flags() + ['-c', src, '-o', wide],
                         capture_output=True, text=True)
    if out.returncode != 0:
        die("%s does not compile with bool widened to 16 bits:\n%s" % (src, out.stderr))
    nm = subprocess.run(['arm-none-eabi-nm', '-S', wide], capture_output=True, text=True).stdout
    for line in nm.splitlines():
        f = line.split()
        if len(f) == 4 and f[3] == sym:
            return (int(f[1], 16) + 1) // 2
    die("%s: no object %s (its DATA_SECTION pragma names it)" % (src, sym))


def data_words(src, obj, tmpdir):
    """An upper bound of src's data in C28x words (see the docstring); obj is
    its isr_path.sh object, read at one word per byte when src defines a
    writable char object."""
    b = data_bytes(obj)
    if b == 0:
        return 0
    if CHAR_OBJECT.search(read(src)):
        return b
    wide = os.path.join(tmpdir, os.path.basename(obj))
    out = subprocess.run(['arm-none-eabi-gcc'] + wide_bool_flags() + ['-c', src, '-o', wide],
                         capture_output=True, text=True)
    if out.returncode != 0:
        die("%s does not compile with bool widened to 16 bits:\n%s" % (src, out.stderr))
    return (data_bytes(wide) + 1) // 2


def callgraph(objdir):
    size, calls = {}, {}
    for f in glob.glob(os.path.join(objdir, '*.ci')):
        for line in read(f).splitlines():
            m = re.match(r'node: \{ title: "([^"]+)" label: "[^"]*?\\n[^"]*?\\n(\d+) bytes', line)
            if m:
                size[m.group(1)] = int(m.group(2))
            m = re.match(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', line)
            if m:
                calls.setdefault(m.group(1), set()).add(m.group(2))

    def node(t, caller):
        local = caller.split(':')[0] + ':' + t
        return local if ':' in caller and local in size else t

    def deepest(n, seen=()):
        if n in seen:
            die("recursion through %s: no stack bound" % n)
        best = max((deepest(node(t, n), seen + (n,)) for t in calls.get(n, ())), default=(0, []))
        return (size.get(n, 0) + best[0], [n.split(':')[-1]] + best[1])

    def root(name):
        for n in size:
            if n == name or n.endswith(':' + name):
                return n
        die("no call-graph node for %s in %s (isr_path.sh builds it)" % (name, objdir))
    return deepest, root, size


def stack_need(objdir, main_c='firmware/f28335/main.c'):
    """The deepest stack in bytes: main's start-up chains (no interrupt
    yet, or held off: hal_isr_pause), or main's frame + the deepest call of
    its loop (the calls after hal_isr_attach in main.c, outside a
    hal_isr_pause ... hal_isr_resume pair) + ctrl_isr's chain on top."""
    deepest, root, size = callgraph(objdir)
    text = read(main_c)
    at = text.find('hal_isr_attach(')
    if at < 0:
        die("%s: no hal_isr_attach( call: cannot tell the loop from start-up" % main_c)
    loop_text = text[at + len('hal_isr_attach('):]
    # calls between hal_isr_pause() and hal_isr_resume(): the ISR held off, so no ISR chain on
    # top (start-up's rule; main's start-up chain above covers them: deepest(main))
    loop_text = re.sub(r'hal_isr_pause\(\);.*?hal_isr_resume\(\);', ' ', loop_text, flags=re.S)
    loop = set(re.findall(r'\b([a-z_][a-z0-9_]*)\s*\(', loop_text)) - {'for', 'if', 'while'}
    start = deepest(root('main'))
    frame = size[root('main')]
    known = [c for c in sorted(loop) if any(n == c or n.endswith(':' + c) for n in size)]
    bg = max([(0, [])] + [deepest(root(c)) for c in known], key=lambda d: d[0])
    isr = deepest(root('ctrl_isr'))
    run = (frame + bg[0] + isr[0], ['main'] + bg[1], isr[1])
    return {'start': start, 'run': run}


def estimate(objdir, mk):
    objs = sorted(glob.glob(os.path.join(objdir, '*.o')))
    if not objs:
        die("no objects in %s (run tools/check/isr_path.sh first)" % objdir)
    code_b = code_w = nv_w = 0
    data_b = data_w = 0
    tmpdir = tempfile.mkdtemp()
    for o in objs:
        src = obj_source(o)
        if src is None:
            continue  # the register fake: not in the image
        data_b += data_bytes(o)
        data_w += data_words(src, o, tmpdir)
        funcs = disassemble(o)
        keep = set(funcs) if placement.in_ram_whole(src, mk) else placement.ram_functions(src)
        nv = placement.section_functions(src)
        for fn in keep & set(funcs):
            code_b += funcs[fn][0]
            code_w += funcs[fn][1]
            nv_w += funcs[fn][1] if fn in nv else 0
    stack = stack_need(objdir)
    # objects placed in sections of their own leave .ebss
    sections = {}
    srcs = [s for s in (obj_source(o) for o in objs) if s is not None]
    for sec, members in data_sections(srcs).items():
        for sym, src in members:
            w = symbol_words(src, sym, tmpdir)
            data_w -= w
            sections.setdefault(sec, []).append((sym, w))
    shutil.rmtree(tmpdir, ignore_errors=True)
    return {'code_bytes': code_b, 'code_words': code_w, 'nv_words': nv_w, 'data_bytes': data_b, 'data_words': data_w,
            'stack': stack, 'sections': sections}


def stack_size_words(mk):
    for opt in placement.make_var(mk, 'LFLAGS'):
        m = re.match(r'--stack_size=(0x[0-9A-Fa-f]+|\d+)$', opt)
        if m:
            return int(m.group(1), 0)
    m = re.search(r'--stack_size=(0x[0-9A-Fa-f]+|\d+)', read(mk))
    if not m:
        die("%s sets no --stack_size" % mk)
    return int(m.group(1), 0)


def stack_line(est, reserve, length, mapped_used):
    """(margin, what, overflow text or None) of the range that holds .stack:
    the need against the reserve (see the header)."""
    st = est['stack']
    need = max(st['start'][0], st['run'][0] + ISR_CONTEXT_WORDS)
    used = reserve if mapped_used is None else mapped_used
    over = (".stack reserve %d words is larger than the range (%d)" % (used, length)) if used > length else None
    what = ("stack reserve %d words (--stack_size, target.mk); need <= %d words at 1 word/B: running "
            "%d B (%s, interrupted by %s) + %d words interrupt context; start-up %d B (%s)"
            % (reserve, need, st['run'][0], ' -> '.join(st['run'][1]), ' -> '.join(st['run'][2]),
               ISR_CONTEXT_WORDS, st['start'][0], ' -> '.join(st['start'][1])))
    return (reserve - need) / float(reserve), what, over


def estimated_use(est, secs):
    """(words, what) the host estimates put in a range holding the sections secs."""
    factor = est['code_words'] / (est['code_bytes'] / 2.0) if est['code_bytes'] else 0.0
    used, parts = 0, []
    for sec in secs:
        if sec == 'Flash28_API':
            continue   # in ramfuncs' UNION: counted with it
        if sec == 'ramfuncs':
            w = est['code_words'] + FASTRTS_WORDS
            parts.append("ramfuncs %d words (RAM code: %d B Thumb-2 -> %d words, factor %.2f; "
                         "+ fast-RTS <= %d; nvfuncs %d of them, last)"
                         % (w, est['code_bytes'], est['code_words'], factor, FASTRTS_WORDS, est['nv_words']))
            if 'Flash28_API' in secs:
                w = max(w, FLASH_API_WORDS)
                parts.append("TI's flash API <= %d words over its start (UNION: while the parameter store writes)"
                             % FLASH_API_WORDS)
        elif sec == '.ebss':
            w = est['data_words'] + RTS_EBSS_WORDS
            parts.append(".ebss <= %d words (%d B Thumb-2 with bool widened, at 1 word per 2 B; "
                         "+ RTS %d)" % (w, 2 * est['data_words'], RTS_EBSS_WORDS))
        elif sec in est['sections']:
            w = sum(x for _s, x in est['sections'][sec])
            parts.append("%s %d words (%s, with bool widened at 1 word per 2 B)" %
                         (sec, w, ', '.join("%s %d" % m for m in est['sections'][sec])))
        else:
            w = 0
            parts.append("%s 0 words (--heap_size=0)" % sec)
        used += w
    return used, ' + '.join(parts)


def api_overlay_line(est, place):
    """(line, failed) of the flash API's overlay of ramfuncs: it must end before
    nvfuncs, which runs while it is there; None when there is no such UNION."""
    if 'Flash28_API' not in place:
        return None
    before = est['code_words'] + FASTRTS_WORDS - est['nv_words']
    ok = before >= FLASH_API_WORDS
    return ("ram_budget: %s flash API overlay: ramfuncs holds %d words before nvfuncs, the API <= %d: %s"
            % ("ok  " if ok else "FAIL", before, FLASH_API_WORDS,
               "nvfuncs out of its reach" if ok else "it would overwrite the code that runs it"), not ok)


def range_lines(est, ranges, place, mapped, reserve):
    """A line per RAM range that holds a section (its use and margin), and
    whether any failed."""
    lines, fail = [], False
    holds = {}
    for sec, rng in place.items():
        holds.setdefault(rng, []).append(sec)
    for rng in sorted(ranges, key=lambda r: (ranges[r][0], ranges[r][1])):
        if rng not in holds:
            continue
        _page, origin, length = ranges[rng]
        secs = holds[rng]
        if '.stack' in secs:
            margin, what, over = stack_line(est, reserve, length, mapped.get(rng))
            if over is not None:
                lines.append("ram_budget: FAIL %s: %s" % (rng, over))
                fail = True
        else:
            if rng in mapped:
                used, what = mapped[rng], "%s: %d words (drive.map)" % (' + '.join(secs), mapped[rng])
            else:
                used, what = estimated_use(est, secs)
            margin = (length - used) / float(length)
        ok = margin >= MARGIN_MIN
        fail = fail or not ok
        lines.append("ram_budget: %s %-8s 0x%06X %5d words: %s; margin %.0f %%" %
                     ("ok  " if ok else "FAIL", rng, origin, length, what, 100.0 * margin))
    return lines, fail


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--cmd', required=True)
    ap.add_argument('--objdir', required=True)
    ap.add_argument('--map')
    ap.add_argument('--mk', default='firmware/f28335/target.mk')
    ap.add_argument('--out')
    a = ap.parse_args()

    est = estimate(a.objdir, a.mk)
    ranges, place = parse_cmd(read(a.cmd), sorted(est['sections']))
    mapped = parse_map(a.map) if a.map and os.path.exists(a.map) else {}
    src = ("drive.map (%s): the linker's used words" % a.map) if mapped else \
          "host estimates (no drive.map): Thumb-2 objects of tools/check/isr_path.sh, see tools/check/ram_budget.py"
    lines = ["ram_budget: %s; a range fails under %d %% free" % (src, round(MARGIN_MIN * 100))]
    body, fail = range_lines(est, ranges, place, mapped, stack_size_words(a.mk))
    lines += body
    api = api_overlay_line(est, place)
    if api is not None:
        lines.append(api[0])
        fail = fail or api[1]
    lines.append("ram_budget: %s" % ("FAILED: a RAM range has under %d %% margin" % round(MARGIN_MIN * 100) if fail
                                     else "every RAM range keeps its margin"))
    text = '\n'.join(lines) + '\n'
    sys.stdout.write(text)
    if a.out:
        with open(a.out, 'w') as f:
            f.write(text)
    return 1 if fail else 0


if __name__ == '__main__':
    sys.exit(main())
