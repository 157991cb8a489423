#!/usr/bin/env python3
"""CPU time of the whole crmorph CLI per corpus pair (issue 16): `morph SRC TGT -o out.svg
--frames 30 -q`, user + system time of the process (all its threads) from wait4, and a hash of
each output so two builds can be checked to give the same bytes.

Usage: python3 tools/auto-cpu.py CORPUS_DIR CRMORPH_BINARY OUT.json
(CORPUS_DIR as made by `node tools/corpus/draw.js`, with its pairs.json)."""
import json, os, signal, subprocess, sys, time
# Piped into `head`, end quietly when the reader has had enough instead of a BrokenPipe trace.
signal.signal(signal.SIGPIPE, signal.SIG_DFL)
root = sys.argv[1]; exe = sys.argv[2]; out = sys.argv[3]
# In a folder of its own: crmorph lists the output's folder once per run (stale temporaries),
# so a crowded TMPDIR would add its own cost to every pair.
OUTPUT = os.path.join(__import__('tempfile').mkdtemp(prefix='crmorph-auto-cpu-'), 'out.svg')
pairs = json.load(open(os.path.join(root, 'pairs.json')))['pairs']
rows = []
for p in pairs:
    s = os.path.join(root, p['source']); t = os.path.join(root, p['target'])
    t0 = time.time()
    if os.path.exists(OUTPUT): os.remove(OUTPUT)
    pr = subprocess.Popen([exe, 'morph', s, t, '-o', OUTPUT, '--frames', '30', '-q'], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(pr.pid, 0)
    err = pr.stderr.read().decode()
    rows.append({'id': p['id'], 'src': p['source'], 'tgt': p['target'], 'cpu': ru.ru_utime + ru.ru_stime, 'sha': __import__('hashlib').sha256(open(OUTPUT,'rb').read()).hexdigest() if os.path.exists(OUTPUT) else '', 'wall': time.time() - t0, 'status': os.waitstatus_to_exitcode(status), 'err': err.strip()[:200]})
json.dump(rows, open(out, 'w'), indent=0)
cpu = sorted(r['cpu'] for r in rows)
n = len(cpu)
def q(f): return cpu[min(n - 1, int(f * n))]
print(f"n={n} median={q(0.5)*1000:.0f}ms p90={q(0.9)*1000:.0f}ms p99={q(0.99)*1000:.0f}ms max={cpu[-1]*1000:.0f}ms fail={sum(r['status']!=0 for r in rows)}")
for r in sorted(rows, key=lambda r: -r['cpu'])[:12]: print(f"{r['cpu']*1000:7.0f} ms {r['id']} {r['src']} -> {r['tgt']}")
