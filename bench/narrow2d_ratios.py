#!/usr/bin/env python3
"""The 2D query table against Box2D v3 and 2.4, from the JSON of the 2D query benchmarks.

    for b in narrow_contact narrow_distance ray_cast ccd; do
      build/release/bench/bench_$b --benchmark_repetitions=7 \\
          --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true \\
          --benchmark_out=$b.json --benchmark_out_format=json
    done
    python3 bench/narrow2d_ratios.py narrow_contact.json narrow_distance.json ray_cast.json ccd.json

Rows pair up by name: a query's sides are the name's segment (or the first segment's suffix
after "_") `collide`, `collide_box2d_target`, `box2d_v3` and `box2d` (2.4). Prints Markdown: ns
per query (median; from items_per_second where a batch is timed, else the CPU time of one
call) for each side, and the ratios v3 / collide and 2.4 / collide (above 1: collide is
faster). A row's collide figure is `collide_box2d_target` where the query has one (time of
impact at Box2D's target separation) and `collide` otherwise. Accuracy counters (sep_at_t,
overlap, hit_rate) are printed beside each side where the benchmark reports them. The
instruction sets come from the runs' context blocks.
"""

import json
import sys
from collections import defaultdict

SIDES = ("collide_box2d_target", "box2d_v3", "collide", "box2d")
ACCURACY = ("sep_at_t", "overlap", "hit_rate")


def split(name):
    """(query, side) of a benchmark name, or None when it is not a side of the race."""
    parts = name.split("/")
    for i, part in enumerate(parts):
        if part in SIDES:
            return "/".join(parts[:i] + parts[i + 1:]), part
    for side in SIDES:
        suffix = "_" + side
        if parts[0].endswith(suffix):
            return "/".join([parts[0][: -len(suffix)]] + parts[1:]), side
    return None


def ns_per_query(bench):
    if "items_per_second" in bench:
        return 1e9 / bench["items_per_second"]
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[bench.get("time_unit", "ns")]
    return bench["cpu_time"] * scale


def main(paths):
    table = defaultdict(dict)
    context = {}
    order = []
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        for key, value in data.get("context", {}).items():
            if "instruction set" in key or "version" in key:
                context[key] = value
        for bench in data["benchmarks"]:
            if bench.get("aggregate_name", "median") != "median":
                continue
            name = bench.get("run_name", bench["name"])
            found = split(name)
            if found is None:
                continue
            query, side = found
            if query not in table:
                order.append(query)
            table[query][side] = bench
    for key in sorted(context):
        print(f"- {key}: {context[key]}")
    print()
    print("| query | collide | Box2D v3 | Box2D 2.4 | v3 / collide | 2.4 / collide |")
    print("| --- | --- | --- | --- | --- | --- |")
    for query in sorted(order):
        sides = table[query]
        ours = sides.get("collide_box2d_target", sides.get("collide"))
        if ours is None:
            continue
        mine = ns_per_query(ours)

        def cell(bench):
            if bench is None:
                return "-"
            text = f"{ns_per_query(bench):.1f} ns"
            extra = [f"{k} {bench[k]:.3g}" for k in ACCURACY if k in bench]
            return text + (f" ({', '.join(extra)})" if extra else "")

        def ratio(bench):
            return "-" if bench is None else f"{ns_per_query(bench) / mine:.2f}x"

        v3 = sides.get("box2d_v3")
        old = sides.get("box2d")
        print(f"| {query} | {cell(ours)} | {cell(v3)} | {cell(old)} | {ratio(v3)} | {ratio(old)} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
