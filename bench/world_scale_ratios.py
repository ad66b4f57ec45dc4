#!/usr/bin/env python3
"""The table of a bench_world_scale or bench_world_scale3d run, from its JSON output.

    build/release/bench/bench_world_scale --benchmark_out=world_scale.json --benchmark_out_format=json
    build/release/bench/bench_world_scale3d --benchmark_out=world_scale3d.json --benchmark_out_format=json
    python3 bench/world_scale_ratios.py world_scale.json [world_scale3d.json more.json ...]

Several files (e.g. one size per run, each run when the machine was quiet) are merged; a later
file's benchmark replaces an earlier one's of the same name.
Prints Markdown: per size and thread count, ns per body per frame of collide's step (everything,
and without its independent check) and of Box2D v3 (the whole b2World_Step, its collision work
without the constraint solver, and pair finding + narrow phase alone), the ratio v3 / collide on
the collision work, each side's speed-up on 2 threads, the growth of the per-body cost from 1e4
to 1e6 bodies, and spawn time per body. 3D rows (bench_world_scale3d: BM_CollideStep3 against
BM_JoltStep3) get their own table: collide's World3D::step without its check beside Jolt's
PhysicsSystem::Update on kinematic bodies, the ratio, and each side's speed-up on 2 threads.
The instruction sets and the load come from the run's context block. With repetitions, the
median of each field.
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


def load_all(paths):
    """The runs of every file merged (later files win), and each file's context merged."""
    runs, ctx = {}, {}
    for path in paths:
        r, c = load(path)
        runs.update(r)
        ctx = {**c, **ctx}
    return runs, ctx


def loads_of(runs):
    return sorted({tuple(round(x, 2) for x in (r.get("load") or [])) for r in runs.values()})


def main(paths):
    runs, ctx = load_all(paths)
    runs2d = {k: v for k, v in runs.items() if not k[0].endswith("3")}
    runs3d = {k: v for k, v in runs.items() if k[0].endswith("3")}
    if runs2d:
        print_2d(runs2d, ctx)
    if runs3d:
        print_3d(runs3d, ctx)


def print_3d(runs, ctx):
    """World3D (BM_CollideStep3) against Jolt's PhysicsSystem (BM_JoltStep3)."""
    sizes = sorted({s for (_, s, _) in runs})
    get = lambda name, n, t, field: runs.get((name, n, t), {}).get(field)
    print(f"\n3D. collide: {ctx.get('collide instruction set', '?')}; "
          f"Jolt: {ctx.get('jolt instruction set', '?')}; "
          f"load averages (1, 5, 15 min) at the start of the runs: {loads_of(runs)}\n")
    print("ns per body per frame. collide: `step` = World3D::step, `no check` = without its "
          "independent check, `discrete` = without the check nor its motion with continuous "
          "collision (`integrate`: Jolt has no continuous collision for kinematic bodies); "
          "Jolt: PhysicsSystem::Update on kinematic bodies (collision work, nothing to solve). "
          "`Jolt/collide` = Jolt / collide no check (above 1: collide faster). Contacts per body "
          "per frame: collide touching pairs (continuous collision's hits included), Jolt "
          "manifolds.\n")
    print("| bodies | threads | collide step | collide no check | collide discrete | Jolt step "
          "| Jolt/collide | Jolt/discrete | collide contacts | Jolt contacts |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n in sizes:
        for t in (1, 2):
            c = get("BM_CollideStep3", n, t, "ns_body_nocheck")
            j = get("BM_JoltStep3", n, t, "ns_body")
            ratio = j / c if j and c else None
            i = get("BM_CollideStep3", n, t, "integrate")
            d = c - i if c and i is not None else None
            print(f"| {n:,} | {t} | {fmt(get('BM_CollideStep3', n, t, 'ns_body'))} | {fmt(c)} | {fmt(d)} "
                  f"| {fmt(j)} | {fmt(ratio)} | {fmt(j / d if j and d else None)} "
                  f"| {fmt(get('BM_CollideStep3', n, t, 'contacts'))} "
                  f"| {fmt(get('BM_JoltStep3', n, t, 'contacts'))} |")
    print("\nSpeed-up on 2 threads (time on 1 / time on 2):\n")
    print("| bodies | collide step | collide no check | Jolt step |")
    print("|---:|---:|---:|---:|")
    for n in sizes:
        cells = []
        for name, field in (("BM_CollideStep3", "ns_body"), ("BM_CollideStep3", "ns_body_nocheck"),
                            ("BM_JoltStep3", "ns_body")):
            one, two = get(name, n, 1, field), get(name, n, 2, field)
            cells.append(fmt(one / two) if one and two else "-")
        print(f"| {n:,} | " + " | ".join(cells) + " |")
    print("\ncollide's phases, ns per body per frame (1 thread / 2 threads):\n")
    phases = ("integrate", "statics", "broad", "pairs", "events", "check")
    print("| bodies | " + " | ".join(phases) + " |")
    print("|---:|" + "---:|" * len(phases))
    for n in sizes:
        cells = [f"{fmt(get('BM_CollideStep3', n, 1, p))} / {fmt(get('BM_CollideStep3', n, 2, p))}"
                 for p in phases]
        print(f"| {n:,} | " + " | ".join(cells) + " |")
    labels = sorted({(k, r["label"]) for k, r in runs.items() if r.get("label")})
    for (name, n, t), label in labels:
        print(f"\nnote: {name}/{n}/{t}: {label}")


def print_2d(runs, ctx):
    """World2D (BM_CollideStep) against Box2D v3 (BM_Box2DStep)."""
    loads = loads_of(runs)
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

    print("\nSpeed-up on 2 threads (time on 1 / time on 2; `paired`: BM_CollideSpeedup, the one-thread "
          "time on each CPU and the two-thread time in alternating blocks of one process, their "
          "harmonic mean over the two-thread time, and against each CPU):\n")
    print("| bodies | collide step | collide no check | collide no check, paired | v3 step | v3 collision |")
    print("|---:|---:|---:|---:|---:|---:|")
    for n in sizes:
        cells = []
        for name, field in (("BM_CollideStep", "ns_body"), ("BM_CollideStep", "ns_body_nocheck"),
                            ("BM_Box2DStep", "ns_body"), ("BM_Box2DStep", "b2_collision")):
            one, two = get(name, n, 1, field), get(name, n, 2, field)
            cells.append(fmt(one / two) if one and two else "-")
        paired = [get("BM_CollideSpeedup", n, 1, f) for f in ("speedup", "speedup_cpu0", "speedup_cpu1")]
        cells.insert(2, f"{fmt(paired[0])} ({fmt(paired[1])} / {fmt(paired[2])})" if paired[0] else "-")
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
