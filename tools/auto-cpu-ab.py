#!/usr/bin/env python3
"""Two crmorph builds compared on the random icon corpus (issue 16), alternately on every pair
(old then new, then new then old), so that a drifting machine weighs on both alike: the CPU time
of `morph SRC TGT -o out.svg --frames 30 -q` (user + system of the process, from wait4), as
tools/auto-cpu.py measures one build. It also hashes both builds' outputs and exit statuses and
lists the pairs where they differ, so one run says both "how much faster" and "same bytes".

Usage: python3 tools/auto-cpu-ab.py CORPUS_DIR OLD_CRMORPH NEW_CRMORPH
(CORPUS_DIR as made by `node tools/corpus/draw.js`, with its pairs.json)."""
import hashlib, json, os, signal, subprocess, sys, tempfile
# Piped into `head`, end quietly when the reader has had enough instead of a BrokenPipe trace.
signal.signal(signal.SIGPIPE, signal.SIG_DFL)

root, old, new = sys.argv[1], sys.argv[2], sys.argv[3]
pairs = json.load(open(os.path.join(root, 'pairs.json')))['pairs']
builds = {'old': old, 'new': new}
cpu = {'old': [], 'new': []}
result = {'old': {}, 'new': {}}
# In a folder of its own: crmorph lists the output's folder once per run (stale temporaries),
# so a crowded TMPDIR would add its own cost to every pair.
out = os.path.join(tempfile.mkdtemp(prefix='crmorph-auto-cpu-ab-'), 'out.svg')
for i, p in enumerate(pairs):
    s, t = os.path.join(root, p['source']), os.path.join(root, p['target'])
    for k in (['old', 'new'] if i % 2 == 0 else ['new', 'old']):
        if os.path.exists(out):
            os.remove(out)
        pr = subprocess.Popen([builds[k], 'morph', s, t, '-o', out, '--frames', '30', '-q'],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, ru = os.wait4(pr.pid, 0)
        cpu[k].append(ru.ru_utime + ru.ru_stime)
        digest = hashlib.sha256(open(out, 'rb').read()).hexdigest() if os.path.exists(out) else ''
        result[k][p['id']] = (os.waitstatus_to_exitcode(status), digest)
for k in ('old', 'new'):
    c = sorted(cpu[k]); n = len(c)
    print(f"{k}: n={n} median={c[n // 2] * 1000:.0f}ms p90={c[int(0.9 * n)] * 1000:.0f}ms "
          f"p99={c[min(n - 1, int(0.99 * n))] * 1000:.0f}ms max={c[-1] * 1000:.0f}ms total={sum(c):.1f}s")
differ = [i for i in result['old'] if result['old'][i] != result['new'][i]]
print(f"outputs: {len(result['old']) - len(differ)} of {len(result['old'])} pairs byte-identical"
      + (f"; differ: {', '.join(differ)}" if differ else ''))
