#!/usr/bin/env python3
"""The table of a bench_world_scale run, from its JSON output.

    build/release/bench/bench_world_scale --benchmark_out=world_scale.json --benchmark_out_format=json
    python3 bench/world_scale_ratios.py world_scale.json [more.json ...]

Several files (e.g. one size per run, each run when the machine was quiet) are merged; a later
file's benchmark replaces an earlier one's of the same name.
Prints Markdown: per size and thread count, ns per body per frame of collide's step (everything,
and without its independent check) and of Box2D v3 (the whole b2World_Step, its collision work
without the constraint solver, and pair finding + narrow phase alone), the ratio v3 / collide on
the collision work, each side's speed-up on 2 threads, the growth of the per-body cost from 1e4
to 1e6 bodies, and spawn time per body. The instruction sets and the load come from the run's
context block. With repetitions, the median of each field.
"""

import json
import statistics
import sys
from collections import defaultdict


def load(path):
    """(benchmark, size, threads) -> {counter: median}, and the context block."""
    with open(path) as f:
        data = json.load(f)
    runs = defaultdict(list)
    load_avg = data.get("context", {}).get("load_avg")
    for b in data["benchmarks"]:
        b["load_avg"] = load_avg
        if b.get("run_type") == "aggregate" or b.get("error_occurred"):
            continue
        parts = [p for p in b.get("run_name", b["name"]).split("/")
                 if p != "real_time" and not p.startswith(("iterations:", "repeats:"))]
        name, size = parts[0], int(parts[1])
        threads = int(parts[2]) if len(parts) > 2 else 1
        runs[(name, size, threads)].append(b)
    out = {}
    for key, rs in runs.items():
        fields = {k for r in rs for k, v in r.items() if isinstance(v, (int, float))}
        out[key] = {k: statistics.median(r[k] for r in rs if k in r) for k in fields}
        out[key]["label"] = rs[0].get("label", "")
        out[key]["load"] = rs[0].get("load_avg")
    return out, data.get("context", {})


def fmt(x):
    return "-" if x is None else (f"{x:.0f}" if x >= 100 else f"{x:.3g}")


def main(paths):
    runs, ctx = {}, {}
    for path in paths:
        r, c = load(path)
        runs.update(r)
        ctx = ctx or c
    loads = sorted({tuple(round(x, 2) for x in (r.get("load") or [])) for r in runs.values()})
    sizes = sorted({s for (_, s, _) in runs})
    get = lambda name, n, t, field: runs.get((name, n, t), {}).get(field)

    print(f"collide: {ctx.get('collide instruction set', '?')}; "
          f"Box2D v3 {ctx.get('box2d v3 version', '?')}: {ctx.get('box2d v3 instruction set', '?')}; "
          f"load averages (1, 5, 15 min) at the start of the runs: {loads}\n")
    print("ns per body per frame. collide: `step` = World2D::step, `no check` = without its "
          "independent check; v3: `step` = b2World_Step (solver included), `collision` = pairs + "
          "collide + transforms + refit + bullets + sensors, `pairs+narrow` = pairs + collide. "
          "`v3/collide` = v3 collision / collide no check.\n")
    print("| bodies | threads | collide bodies | collide step | collide no check | v3 step | v3 collision "
          "| v3 pairs+narrow | v3/collide |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n in sizes:
        for t in (1, 2):
            c = get("BM_CollideStep", n, t, "ns_body_nocheck")
            b = get("BM_Box2DStep", n, t, "b2_collision")
            ratio = b / c if b and c else None
            print(f"| {n:,} | {t} | {fmt(get('BM_CollideStep', n, t, 'bodies'))} "
                  f"| {fmt(get('BM_CollideStep', n, t, 'ns_body'))} | {fmt(c)} "
                  f"| {fmt(get('BM_Box2DStep', n, t, 'ns_body'))} | {fmt(b)} "
                  f"| {fmt(get('BM_Box2DStep', n, t, 'b2_broad_narrow'))} | {fmt(ratio)} |")

    print("\nSpeed-up on 2 threads (time on 1 / time on 2):\n")
    print("| bodies | collide step | collide no check | v3 step | v3 collision |")
    print("|---:|---:|---:|---:|---:|")
    for n in sizes:
        cells = []
        for name, field in (("BM_CollideStep", "ns_body"), ("BM_CollideStep", "ns_body_nocheck"),
                            ("BM_Box2DStep", "ns_body"), ("BM_Box2DStep", "b2_collision")):
            one, two = get(name, n, 1, field), get(name, n, 2, field)
            cells.append(fmt(one / two) if one and two else "-")
        print(f"| {n:,} | " + " | ".join(cells) + " |")

    lo, hi = 10000, max(sizes) if sizes else 0
    if lo in sizes and hi > lo:
        print(f"\nGrowth of the per-body cost from {lo:,} to {hi:,} bodies (1 = linear in N):\n")
        print("| threads | collide step | collide no check | v3 step | v3 collision |")
        print("|---:|---:|---:|---:|---:|")
        for t in (1, 2):
            cells = []
            for name, field in (("BM_CollideStep", "ns_body"), ("BM_CollideStep", "ns_body_nocheck"),
                                ("BM_Box2DStep", "ns_body"), ("BM_Box2DStep", "b2_collision")):
                a, b = get(name, lo, t, field), get(name, hi, t, field)
                cells.append(fmt(b / a) if a and b else "-")
            print(f"| {t} | " + " | ".join(cells) + " |")

    print("\nv3 on 2 threads: its task callbacks on oneTBB (the table above) against its built-in "
          "scheduler, ns per body per frame:\n")
    print("| bodies | oneTBB step | built-in step | oneTBB collision | built-in collision |")
    print("|---:|---:|---:|---:|---:|")
    for n in sizes:
        print(f"| {n:,} | {fmt(get('BM_Box2DStep', n, 2, 'ns_body'))} "
              f"| {fmt(get('BM_Box2DStepOwnScheduler', n, 2, 'ns_body'))} "
              f"| {fmt(get('BM_Box2DStep', n, 2, 'b2_collision'))} "
              f"| {fmt(get('BM_Box2DStepOwnScheduler', n, 2, 'b2_collision'))} |")

    print("\nSpawn (cli::make_scene, 1 thread) and memory (heap in use per body: collide's whole scene, "
          "v3's world built from it):\n")
    print("| bodies asked | placed | statics | spawn ns per body | collide bytes per body "
          "| v3 bytes per body | note |")
    print("|---:|---:|---:|---:|---:|---:|---|")
    for n in sizes:
        r = runs.get(("BM_Spawn", n, 1))
        if r:
            print(f"| {n:,} | {fmt(r.get('bodies'))} | {fmt(r.get('statics'))} | {fmt(r.get('ns_body'))} "
                  f"| {fmt(r.get('heap_per_body'))} | {fmt(get('BM_Box2DStep', n, 1, 'heap_per_body'))} "
                  f"| {r.get('label', '')} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
