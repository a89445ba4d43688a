#!/usr/bin/env python3
"""Summarise biota_bench_lbm_layout JSON files: best of all runs, wall and CPU-time MLUPS, % of the
STREAM-triad roofline for the variant's bytes and for the 16Q in-place bound (100^3 cells assumed)."""
import json,sys,collections
# usage: summarize.py files...  -> best-of over all repetitions, wall and CPU-time figures
wall=collections.defaultdict(float); cpu=collections.defaultdict(float); lab={}; bpu={}
bw=bwc=0; gf=1e9
for fn in sys.argv[1:]:
    d=json.load(open(fn))
    for b in d['benchmarks']:
        if b.get('run_type')=='aggregate': continue
        n=b['run_name']
        if 'GBps' in b:
            bw=max(bw,b['GBps']); bwc=max(bwc,480.0/b['cpu_time'])
        elif 'MLUPS' in b:
            wall[n]=max(wall[n],b['MLUPS']); cpu[n]=max(cpu[n],1000.0/b['cpu_time']); lab[n]=b['label']; bpu[n]=b['B_per_update']
        elif 'Ghost' in n:
            gf=min(gf,b['cpu_time'])
print(f"best triad: wall {bw:.2f} GB/s, cpu-time {bwc:.2f} GB/s; ghost fill D3Q19 best cpu {gf:.2f} ms")
print("| variant | B/update | MLUPS wall | MLUPS cpu | % roof own B (cpu) | % roof 16Q in-place (cpu) | % roof own B (wall) |")
for n in sorted(wall, key=lambda n:(lab[n].split()[0], lab[n].split()[1])):
    q=int(lab[n].split()[0][-2:])
    print(f"| {lab[n]} | {bpu[n]:.0f} | {wall[n]:.1f} | {cpu[n]:.1f} | {100*cpu[n]*bpu[n]/(bwc*1e3):.0f}% | {100*cpu[n]*16*q/(bwc*1e3):.0f}% | {100*wall[n]*bpu[n]/(bw*1e3):.0f}% |")
