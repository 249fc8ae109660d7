#!/usr/bin/env python3
"""deps.py - the dependency gate of `make check` (run by layers.sh): the
C code of control/, hal/, firmware/ and tools/ points down only and has
no loop, between folders or inside one.

A unit is a source with its header of the same name in the same folder
(app.c and app.h), or a header alone. A unit uses another when one of its
files includes the other's header (#include "x.h", looked up beside the
file, then by name), or when one of its functions calls a function that
the other alone defines (so a loop through a declaration written by hand
counts too; a name two units define, an interface such as hal.h's with a
board each, is left to its header's include). Read as text (csrc.py): no
compiler, so a seeded copy of the tree is checked in a moment.

The order, bottom up, one group a line (folders in a group are siblings:
neither uses the other):
  control/<room>           one group per room, in control/rooms.mk's order
  hal                      (hal.h)
  hal/sim, hal/f28335
  firmware/<room>          one group per room, in firmware/rooms.mk's order
  tools/sil
  tools/bench
A unit may use units of its own folder and of lower groups. Fails (exit 1)
naming the files and the names that tie them:
  1. a unit uses one of a higher group or of a sibling folder;
  2. units use each other in a loop (a strongly connected set of more
     than one unit), inside a folder too.

Usage: deps.py [--root DIR]
"""
import argparse
import os
import re
import sys

import csrc


def layer_order(root):
    rooms = re.search(r'(?m)^FIRMWARE_ROOMS\s*:=\s*(.*)$', csrc.read(os.path.join(root, 'firmware/rooms.mk')))
    if not rooms:
        sys.exit("deps: error: firmware/rooms.mk has no FIRMWARE_ROOMS line")
    control = re.search(r'(?m)^CONTROL_ROOMS\s*:=\s*(.*)$', csrc.read(os.path.join(root, 'control/rooms.mk')))
    if not control:
        sys.exit("deps: error: control/rooms.mk has no CONTROL_ROOMS line")
    return ([[d] for d in control.group(1).split()] + [['hal'], ['hal/sim', 'hal/f28335']] +
            [['firmware/' + r] for r in rooms.group(1).split()] + [['tools/sil'], ['tools/bench']])


def sources(root, dirs):
    out = []
    for d in dirs:
        full = os.path.join(root, d)
        if os.path.isdir(full):
            out += sorted(os.path.join(d, f) for f in os.listdir(full) if f.endswith(('.c', '.h')))
    return out


def unit_of(path):
    return os.path.splitext(path)[0]


def resolve(root, src, name, by_name):
    """The scanned file `#include "name"` in src opens, or None (outside the scanned tree)."""
    beside = os.path.normpath(os.path.join(os.path.dirname(src), name))
    if os.path.isfile(os.path.join(root, beside)):
        return beside
    return by_name.get(os.path.basename(name)) if '/' not in name else None


def graph(root, files):
    """{unit: {used unit: set of what ties them (a header, or names called)}}."""
    by_name = {os.path.basename(f): f for f in files}
    edges = {unit_of(f): {} for f in files}
    definers = {}
    funcs = {}
    for f in files:
        if f.endswith('.c'):
            funcs[f] = csrc.functions(os.path.join(root, f))
            for name, (head, _calls) in funcs[f].items():
                if 'static' not in head:
                    definers.setdefault(name, set()).add(unit_of(f))
    for f in files:
        u = unit_of(f)
        for name in csrc.includes(os.path.join(root, f)):
            target = resolve(root, f, name, by_name)
            if target is not None and unit_of(target) != u:
                edges[u].setdefault(unit_of(target), set()).add('#include "%s"' % name)
        for _name, (_head, calls) in funcs.get(f, {}).items():
            for c in calls:
                owners = definers.get(c, set())
                if len(owners) == 1 and u not in owners:
                    edges[u].setdefault(next(iter(owners)), set()).add(c + '()')
    return edges


def loops(edges):
    """The strongly connected sets of more than one unit (Tarjan, iterative)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                scc = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    scc.append(w)
                    if w == v:
                        break
                if len(scc) > 1:
                    out.append(sorted(scc))
    return out


def check(root):
    order = layer_order(root)
    group = {d: i for i, ds in enumerate(order) for d in ds}
    files = sources(root, list(group))
    edges = graph(root, files)
    fails = []
    for u in sorted(edges):
        for v, why in sorted(edges[u].items()):
            du, dv = os.path.dirname(u), os.path.dirname(v)
            if du != dv and group[dv] >= group[du]:
                kind = 'a sibling' if group[dv] == group[du] else 'a higher one'
                fails.append("%s -> %s (%s): %s/ uses %s/, %s" % (u, v, ', '.join(sorted(why)), du, dv, kind))
    for scc in loops(edges):
        ties = ["%s -> %s: %s" % (u, v, ', '.join(sorted(edges[u][v])))
                for u in scc for v in sorted(edges[u]) if v in scc]
        fails.append("a loop of %d units: %s\n    %s" % (len(scc), ', '.join(scc), '\n    '.join(ties)))
    n_edges = sum(len(v) for v in edges.values())
    return fails, len(edges), n_edges, order


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--root', default='.', help='the tree to check (default: here)')
    a = ap.parse_args()
    fails, n_units, n_edges, order = check(a.root)
    for f in fails:
        print('FAIL ' + f)
    if fails:
        print("deps: FAILED (%d)" % len(fails))
        return 1
    print("deps: %d units, %d arrows, all down the order %s; no loop"
          % (n_units, n_edges, ' < '.join('|'.join(ds) for ds in order)))
    return 0


if __name__ == '__main__':
    sys.exit(main())
