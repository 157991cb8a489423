#!/usr/bin/env python3
"""Inclusive instruction counts summed over several callgrind profiles (issue 16): where a set
of corpus pairs spends its time, by function. `callgrind_annotate` reads one profile at a time
(its further arguments are source files), so each profile is annotated on its own and the
counts are added here. A function's count in one profile is its largest inclusive line there;
rayon's worker threads are counted apart from the main thread, so shares under `main` miss the
work they hand over.

With --self, each function's own cost (its lines, not its callees') is summed instead.

Usage: python3 tools/callgrind-sum.py [--top N] [--self] CALLGRIND_OUT...
(profiles as `valgrind --tool=callgrind --callgrind-out-file=F crmorph morph ...` writes them,
from a build with debug information)."""
import collections, re, subprocess, sys

args = sys.argv[1:]
top, inclusive = 40, True
while args[:1] in (['--top'], ['--self']):
    if args[0] == '--top':
        top, args = int(args[1]), args[2:]
    else:
        inclusive, args = False, args[1:]
if not args:
    sys.exit(__doc__)
line_re = re.compile(r'\s*([\d,]+) \(\s*[\d.]+%\)\s+(\S+?):(.+?)(?: \[.*\])?$')
total, summed = 0, collections.Counter()
for path in args:
    out = subprocess.run(['callgrind_annotate', f'--inclusive={"yes" if inclusive else "no"}',
                          '--threshold=100', path],
                         capture_output=True, text=True, check=True).stdout
    largest = {}
    for line in out.splitlines():
        if 'PROGRAM TOTALS' in line:
            total += int(line.split()[0].replace(',', ''))
            continue
        m = line_re.match(line)
        if not m:
            continue
        count, source, function = int(m.group(1).replace(',', '')), m.group(2), m.group(3)
        if not inclusive:
            # Own cost: every line under the function's name, its inlined std and dependency
            # code included.
            largest[function] = largest.get(function, 0) + count
            continue
        # Lines attributed to inlined std or dependency code inside a crmorph function repeat
        # that function's name with part of its inclusive cost; its own line is the one from
        # crmorph's sources.
        if 'crmorph::' in function and ('/rustc/' in source or '.cargo/' in source):
            continue
        largest[function] = max(largest.get(function, 0), count)
    summed.update(largest)
print(f'{len(args)} profiles, {total:,} instructions')
for function, count in summed.most_common(top):
    print(f'{100 * count / total:5.1f} %  {function[:150]}')
