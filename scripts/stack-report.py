#!/usr/bin/env python3
"""Worst-case stack of the firmware's step functions, from gcc's own data.

Reads the call-graph files that -fcallgraph-info=su writes next to every
object (<file>.c.ci, VCG text: one node per function with its frame size from
-fstack-usage, one edge per call site) under BUILD/firmware, and for every
root function (default: each law step aocs_<law>_step and the executive's
aocs_exec_step*) computes the deepest path of the call tree: the largest sum
of frames from the root down to a leaf. That is the stack the call needs on
top of its caller's frame.

Marks in the table:
  +lib  the path reaches functions without frame data (newlib/libgcc: sqrtf,
        memset, __aeabi_*): their frames are not included; the callees are
        listed under the table.
  dyn   some frame on the path is dynamic (alloca/VLA): not a bound. The
        firmware rules forbid both, so this should never show.
  REC   recursion found (forbidden by the firmware rules): no bound.

Usage: stack-report.py [--root REGEX] NAME=BUILD_DIR [NAME=BUILD_DIR ...]
"""
import argparse
import glob
import os
import re
import sys

NODE_RE = re.compile(r'^node: \{ title: "([^"]*)" label: "([^"]*)"')
EDGE_RE = re.compile(r'^edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)"')
BYTES_RE = re.compile(r'\\n(\d+) bytes \(([a-z,]+)\)')
DEFAULT_ROOT = r'^aocs_\w+_step(_no_input)?$'


class Graph:
    def __init__(self):
        self.frame = {}      # title -> bytes
        self.kind = {}       # title -> static | dynamic | dynamic,bounded
        self.calls = {}      # title -> set of callee titles
        self.display = {}    # title -> short name

    def load(self, build_dir):
        files = sorted(glob.glob(os.path.join(build_dir, 'firmware', '**', '*.ci'), recursive=True))
        for path in files:
            with open(path, encoding='utf-8', errors='replace') as fh:
                for line in fh:
                    m = NODE_RE.match(line)
                    if m:
                        title, label = m.group(1), m.group(2)
                        b = BYTES_RE.search(label)
                        self.display.setdefault(title, label.split('\\n', 1)[0])
                        if b:
                            self.frame[title] = int(b.group(1))
                            self.kind[title] = b.group(2)
                        continue
                    m = EDGE_RE.match(line)
                    if m:
                        self.calls.setdefault(m.group(1), set()).add(m.group(2))
        return len(files)

    def worst(self, root):
        """(bytes, path, external callees, dynamic, recursive) of the deepest path."""
        memo = {}
        state = {'rec': False}

        def visit(fn, on_path):
            if fn in memo:
                return memo[fn]
            if fn in on_path:
                state['rec'] = True
                return (0, [fn + ' (recursion)'], set(), False)
            if fn not in self.frame:
                return (0, [], {self.display.get(fn, fn)}, False)
            on_path.add(fn)
            best = (0, [], set(), False)
            ext = set()
            dyn = self.kind.get(fn, 'static') != 'static'
            for callee in sorted(self.calls.get(fn, ())):
                sub = visit(callee, on_path)
                ext |= sub[2]
                dyn = dyn or sub[3]
                if sub[0] > best[0] or (sub[0] == best[0] and not best[1] and sub[1]):
                    best = sub
            on_path.discard(fn)
            res = (self.frame[fn] + best[0],
                   ['%s(%d)' % (self.display.get(fn, fn), self.frame[fn])] + best[1],
                   ext, dyn)
            memo[fn] = res
            return res

        total, path, ext, dyn = visit(root, set())
        return total, path, ext, dyn, state['rec']


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--root', default=DEFAULT_ROOT, help='regex of root function names')
    ap.add_argument('--paths', action='store_true', help='print the deepest call path of each root')
    ap.add_argument('builds', nargs='+', help='NAME=BUILD_DIR')
    args = ap.parse_args()

    graphs = []
    for spec in args.builds:
        name, _, path = spec.partition('=')
        g = Graph()
        if not path or g.load(path) == 0:
            print('stack-report: no .ci files under %s/firmware (build with the ARM toolchain file)'
                  % (path or spec), file=sys.stderr)
            return 1
        graphs.append((name, g))

    root_re = re.compile(args.root)
    roots = sorted({t for _, g in graphs for t in g.frame if root_re.match(t)})
    if not roots:
        print('stack-report: no function matches %s' % args.root, file=sys.stderr)
        return 1

    width = max(len(r) for r in roots)
    header = '%-*s' % (width, 'root function') + ''.join('  %16s' % n for n, _ in graphs)
    print('Worst-case stack per step call, bytes (deepest path of the call tree, -fstack-usage frames)')
    print(header)
    print('-' * len(header))
    externals = {}
    bad = False
    details = []
    for r in roots:
        cells = []
        for name, g in graphs:
            if r not in g.frame:
                cells.append('  %16s' % '-')
                continue
            total, path, ext, dyn, rec = g.worst(r)
            marks = []
            if ext:
                marks.append('+lib')
                for e in ext:
                    externals.setdefault(e, set()).add(name)
            if dyn:
                marks.append('dyn')
            if rec:
                marks.append('REC')
                bad = True
            cells.append('  %16s' % ('%d %s' % (total, ' '.join(marks))).strip())
            details.append((r, name, total, path))
        print('%-*s' % (width, r) + ''.join(cells))
    if externals:
        print('\n+lib: library callees without frame data (not included): '
              + ', '.join(sorted(externals)))
    if args.paths:
        print('\nDeepest path (frame bytes per function):')
        for r, name, total, path in details:
            print('  %-10s %-*s %5d  %s' % (name, width, r, total, ' > '.join(path)))
    return 2 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
