#!/usr/bin/env python3
"""placement.py - where each function of the F28335 image runs, read from
the sources, and the ISR-path placement gate of `make check`.

Placement (control/c28x_portable.h): the directories target.mk names in
RAMFUNC_ALL (control/) run from RAM whole (--ramfunc=on), but for the files
it names in RAMFUNC_ALL_EXCEPT; elsewhere, and in those files, a function's
definition says where it runs:
  RAMFUNC    in RAM (.TI.ramfunc, copied at start-up): the control ISR's path
  FLASHFUNC  in flash although the ISR calls it, on purpose (a state that
             does not control the motor for the user: commissioning,
             start-up steps, build levels), with the flash's wait states
  neither    in flash, and never on the ISR path

Usage: placement.py --map ISR_PATH.MAP [--mk TARGET_MK]
  Fails (exit 1), naming file and function, when
  1. a function of the ISR path (the functions linked into isr_path.sh's
     image, its map file) outside RAMFUNC_ALL carries neither marker: it
     would run from flash;
  2. a function that a marked function of the same file calls carries
     no marker itself: gcc may have inlined it for the map, cl2000 may not
     (a RAMFUNC function may call a FLASHFUNC one: a state's step in flash).
ram_budget.py imports ram_functions() and in_ram_whole() from here.
"""
import argparse
import glob
import os
import re
import sys

import csrc

MARKERS = ('RAMFUNC', 'FLASHFUNC')
# Code placed in RAM by a section of its own rather than a marker: the
# parameter store's writer, which runs while TI's flash API is over the
# start of ramfuncs (hal/f28335/hal_f28335_nv.c, f28335_flash.cmd).
RAM_SECTIONS = ('nvfuncs',)
CODE_SECTION = re.compile(r'#pragma\s+CODE_SECTION\s*\(\s*(\w+)\s*,\s*"(\w+)"\s*\)')


def functions(path):
    """{name: (marker or None, static, names called)} of the definitions in path."""
    return {name: (next((w for w in head if w in MARKERS), None), 'static' in head, calls)
            for name, (head, calls) in csrc.functions(path).items()}


def make_var(mk, name):
    m = re.search(r'(?m)^' + name + r'\s*:=\s*(.*)$', csrc.read(mk))
    return m.group(1).split() if m else []


def in_ram_whole(src, mk):
    """True when src lies in a directory that target.mk runs from RAM whole, and is not one of its exceptions."""
    return (any(src.startswith(d.rstrip('/') + '/') for d in make_var(mk, 'RAMFUNC_ALL')) and
            src not in make_var(mk, 'RAMFUNC_ALL_EXCEPT'))


def section_functions(src, sections=RAM_SECTIONS):
    """The functions src places in one of sections by a CODE_SECTION pragma."""
    return {fn for fn, sec in CODE_SECTION.findall(csrc.read(src)) if sec in sections}


def ram_functions(src):
    """The functions src places in RAM (RAMFUNC, or a CODE_SECTION of RAM_SECTIONS)."""
    return {n for n, (mark, _s, _c) in functions(src).items() if mark == 'RAMFUNC'} | section_functions(src)


def image_sources():
    """The C sources of control/, firmware/ and hal/ (the register fake's are under tests/)."""
    return sorted(f for d in ('control', 'firmware', 'hal') for f in glob.glob(d + '/**/*.c', recursive=True))


def map_functions(map_path):
    """[(function, source)] of the ISR-path image (ld's map, -ffunction-sections):
    the objects are named after their sources, '/' as '_' (isr_path.sh)."""
    out, name, on = [], '', False
    for line in csrc.read(map_path).splitlines():
        if line.startswith('Linker script and memory map'):
            on = True
            continue
        if not on:
            continue
        f = line.split()
        if name:
            out.append((name, f[-1]))
            name = ''
        elif line.startswith(' .text.'):
            fn = f[0][len('.text.'):]
            if len(f) >= 4:
                out.append((fn, f[-1]))
            else:
                name = fn
    return [(fn.split('.')[0], obj) for fn, obj in out]  # gcc's clones (.isra.0, .constprop.0) are the function


def source_of(obj, sources):
    """build/check/isr/firmware_app.c.o -> firmware/app/app.c (of the sources given)."""
    base = os.path.basename(obj)
    for s in sources:
        if base == s.replace('/', '_') + '.o':
            return s
    return None


def check(map_path, mk, sources):
    fails = []
    defs = {s: functions(s) for s in sources if not in_ram_whole(s, mk) and not s.startswith('tests/')}
    for fn, obj in map_functions(map_path):
        src = source_of(obj, sources)
        if src is None or src not in defs:
            continue  # the register fake, or a directory in RAM whole
        mark = defs[src].get(fn, (None,))[0]
        if mark is None:
            fails.append("%s: %s is on the ISR path without RAMFUNC (or FLASHFUNC, on purpose): it would run "
                         "from flash" % (src, fn))
    for src, fns in sorted(defs.items()):
        for caller, (mark, _static, calls) in sorted(fns.items()):
            if mark is None:
                continue
            for callee in sorted(calls & set(fns)):
                if fns[callee][0] is None:
                    fails.append("%s: %s, called by %s %s, is neither RAMFUNC nor FLASHFUNC: where cl2000 does "
                                 "not inline it as gcc did, it runs from flash unmarked" % (src, callee, mark, caller))
    return fails


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--map', required=True, help="isr_path.sh's map of the ISR-path image")
    ap.add_argument('--mk', default='firmware/f28335/target.mk')
    ap.add_argument('sources', nargs='+', help='the image\'s C sources')
    a = ap.parse_args()
    fails = check(a.map, a.mk, a.sources)
    for f in fails:
        print('FAIL ' + f)
    marked = sum(1 for s in a.sources if not s.startswith('tests/')
                 for m, _st, _c in functions(s).values() if m is not None)
    if not fails:
        but = make_var(a.mk, 'RAMFUNC_ALL_EXCEPT')
        print("placement: every ISR-path function outside %s%s is RAMFUNC or FLASHFUNC (%d marked definitions)"
              % (' '.join(make_var(a.mk, 'RAMFUNC_ALL')) or '-', (' (but %s)' % ' '.join(but)) if but else '', marked))
    return 1 if fails else 0


if __name__ == '__main__':
    sys.exit(main())
