#!/usr/bin/env python3
"""Paired rounds of librt_bench's librt-vs-Embree rows for two or more builds (issue 40).

Usage: pair_bvh_rows.py FILTER ROUNDS OUT.json NAME=BENCH [NAME=BENCH ...]

Each round runs every librt_bench binary once over the rows FILTER selects
(--benchmark_min_time=0.3), the order rotated from round to round. A row's ratio
(librt / Embree rays per second) is paired inside the row, so a build's effect is the
quotient of its ratio over the first build's in the same round; the script prints, per row,
the median ratio of each build and the median (min-max) quotient over the rounds. OUT.json
keeps every round's counters (ratio, librt_Mrays, embree_Mrays, hit%) per build, written
after each round. LIBRT_DATA_DIR defaults to /work/shared/data.

The stream rows (<mesh>/librt_stream_vs_embree/...) pair four engines in the row; for them a
second table prints, per build, the median (min-max) over the rounds of each of their ratios:
librt stream / Embree stream, / Embree single rays, / librt single rays, and librt single /
Embree single.
"""
import json, os, subprocess, sys, statistics
flt, rounds, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
bins = [a.split('=', 1) for a in sys.argv[4:]]
env = dict(os.environ)
env.setdefault('LIBRT_DATA_DIR', '/work/shared/data')
STREAM_KEYS = ('ratio', 'ratio_embree1', 'ratio_librt1', 'ratio_single')
res = {name: [] for name, _ in bins}  # name -> list of {row: counters}
for r in range(rounds):
    order = bins[r % len(bins):] + bins[:r % len(bins)]
    for name, path in order:
        tmp = out + '.' + name + '.tmp.json'
        subprocess.run([path, '--benchmark_filter=' + flt, '--benchmark_min_time=0.3',
                        '--benchmark_out=' + tmp, '--benchmark_out_format=json'], env=env,
                       capture_output=True, text=True, check=True)
        j = json.load(open(tmp))
        rows = {b['name'].replace('/manual_time', ''): {k: b.get(k, 0) for k in
                STREAM_KEYS + ('librt_Mrays', 'embree_Mrays', 'librt1_Mrays', 'embree1_Mrays',
                               'hit%')} for b in j['benchmarks']}
        res[name].append(rows)
    print(f'round {r+1} done, load {os.getloadavg()}', file=sys.stderr, flush=True)
    json.dump(res, open(out, 'w'), indent=1)
base = bins[0][0]
rows = list(res[base][0].keys())
hdr = f"{'row':48s}" + ''.join(f'{n:>9s}' for n, _ in bins) + ''.join(
    f'{n + "/" + base:>26s}' for n, _ in bins[1:])
print(hdr)
for row in rows:
    line = f'{row:48s}'
    for n, _ in bins:
        line += f"{statistics.median(x[row]['ratio'] for x in res[n]):9.3f}"
    for n, _ in bins[1:]:
        q = [res[n][i][row]['ratio'] / res[base][i][row]['ratio'] for i in range(rounds)]
        line += f'   {statistics.median(q):.3f} ({min(q):.3f}-{max(q):.3f})'
    print(line)

stream_rows = [r for r in rows if res[base][0][r].get('ratio_librt1')]
if stream_rows:
    def mm(v):
        return f'{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})'
    print()
    print(f"{'stream row':44s} {'build':>8s}" + ''.join(
        f'{k:>22s}' for k in ('stream/embree_stream', 'stream/embree_single', 'stream/librt_single',
                              'librt1/embree1')))
    for row in stream_rows:
        for n, _ in bins:
            print(f'{row:44s} {n:>8s}' + ''.join(
                f"{mm([x[row][k] for x in res[n]]):>22s}" for k in STREAM_KEYS))
