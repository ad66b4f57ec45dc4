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
impact at Box2D's target separation) and `collide` otherwise. A batched query of collide's
(RIVALS_FROM) is set against the rivals' one-call-per-pair row on the same pairs. Accuracy counters (sep_at_t,
overlap, hit_rate) are printed beside each side where the benchmark reports them. The
instruction sets come from the runs' context blocks.
"""

import json
import sys
from collections import defaultdict

SIDES = ("collide_box2d_target", "box2d_v3", "collide", "box2d")

# The README's row labels, in its order; queries not listed follow under their benchmark names.
LABELS = {
    "BM_Contact_Poly4/1024": "manifold, 4-gons, 1024 pairs (v3 `b2CollidePolygons`)",
    "BM_Contact_Poly4/64": "manifold, 4-gons, 64 pairs (in L1)",
    "BM_Contact_Poly8/1024": "manifold, 8-gons, 1024 pairs",
    "BM_Contact_Poly8/64": "manifold, 8-gons, 64 pairs",
    "BM_Contact_CirclePoly/1024":
        "manifold, circle-6-gon, 1024 pairs (`b2CollidePolygonAndCircle`)",
    "BM_Contact_CirclePoly/64": "manifold, circle-6-gon, 64 pairs",
    "BM_Contact_CapsulePoly/1024":
        "manifold, capsule-6-gon, 1024 pairs (`b2CollidePolygonAndCapsule`)",
    "BM_Contact_CapsulePoly/64": "manifold, capsule-6-gon, 64 pairs",
    "BM_Contact_Poly4_shuffled/1024":
        "manifold, 4-gons, 1024 pairs, shuffled (an order no branch predictor learns)",
    "BM_Contact_Poly4_shuffled/64": "manifold, 4-gons, 64 pairs, shuffled",
    "BM_Contact_Poly8_shuffled/1024": "manifold, 8-gons, 1024 pairs, shuffled",
    "BM_Contact_Poly8_shuffled/64": "manifold, 8-gons, 64 pairs, shuffled",
    "BM_Contact_CirclePoly_shuffled/1024": "manifold, circle-6-gon, 1024 pairs, shuffled",
    "BM_Contact_CirclePoly_shuffled/64": "manifold, circle-6-gon, 64 pairs, shuffled",
    "BM_Contact_CirclePoly_batch/1024": "manifold, circle-6-gon, 1024 pairs, batched (rivals: the one-by-one row's)",
    "BM_Contact_CirclePoly_batch/64": "manifold, circle-6-gon, 64 pairs, batched",
    "BM_Contact_CirclePoly_batch_shuffled/1024": "manifold, circle-6-gon, 1024 pairs, batched, shuffled",
    "BM_Contact_CirclePoly_batch_shuffled/64": "manifold, circle-6-gon, 64 pairs, batched, shuffled",
    "BM_Contact_CapsulePoly_shuffled/1024": "manifold, capsule-6-gon, 1024 pairs, shuffled",
    "BM_Contact_CapsulePoly_shuffled/64": "manifold, capsule-6-gon, 64 pairs, shuffled",
    "BM_Distance_Poly4": "distance, 4-gons, cold (`b2ShapeDistance`)",
    "BM_Distance_Poly8": "distance, 8-gons, cold",
    "BM_Distance_CirclePoly8": "distance, circle-8-gon, cold",
    "BM_Distance_Poly64Poly8": "distance, 64-gon-8-gon, cold (v3 holds at most 8 points)",
    "BM_DistanceWarm_Poly8": "distance, 8-gons, warm-started",
    "BM_DistanceWarm_Poly64Poly8": "distance, 64-gon-8-gon, warm-started",
    "BM_Distance_Poly4_shuffled": "distance, 4-gons, cold, shuffled",
    "BM_Distance_Poly8_shuffled": "distance, 8-gons, cold, shuffled",
    "BM_Distance_CirclePoly8_shuffled": "distance, circle-8-gon, cold, shuffled",
    "BM_Distance_Poly64Poly8_shuffled": "distance, 64-gon-8-gon, cold, shuffled",
    "BM_Overlap_Poly4":
        "overlap, 4-gons, mostly separated (v3: `b2ShapeDistance` < 10 FLT_EPSILON)",
    "BM_Overlap_Poly8": "overlap, 8-gons, mostly separated",
    "BM_Overlap_Poly4Touching": "overlap, 4-gons, mostly overlapping",
    "BM_Overlap_Poly8Touching": "overlap, 8-gons, mostly overlapping",
    "BM_Overlap_Poly4_shuffled": "overlap, 4-gons, mostly separated, shuffled",
    "BM_Overlap_Poly8_shuffled": "overlap, 8-gons, mostly separated, shuffled",
    "BM_Overlap_Poly4Touching_shuffled": "overlap, 4-gons, mostly overlapping, shuffled",
    "BM_Overlap_Poly8Touching_shuffled": "overlap, 8-gons, mostly overlapping, shuffled",
    "BM_PolygonRaycast/4/15": "ray cast, 4-gon, 16 shapes (in L1) (`b2RayCastPolygon`)",
    "BM_PolygonRaycast/4/4095": "ray cast, 4-gon, 4096 shapes",
    "BM_PolygonRaycast/8/15": "ray cast, 8-gon, 16 shapes",
    "BM_PolygonRaycast/8/4095": "ray cast, 8-gon, 4096 shapes",
    "BM_CircleRaycast/0/15": "ray cast, circle, 16 shapes (`b2RayCastCircle`)",
    "BM_CircleRaycast/0/4095": "ray cast, circle, 4096 shapes",
    "BM_CapsuleRaycast/0/15": "ray cast, capsule, 16 shapes (`b2RayCastCapsule`)",
    "BM_CapsuleRaycast/0/4095": "ray cast, capsule, 4096 shapes",
    "BM_ShapeCast/box_box": "shape cast, box-box (`b2ShapeCast`)",
    "BM_ShapeCast/poly8_poly8": "shape cast, 8-gons",
    "BM_ShapeCast/circle_poly8": "shape cast, circle-8-gon",
    "BM_ShapeCast/capsule_poly8": "shape cast, capsule-8-gon",
    "BM_ToiTranslation/box_box": "time of impact, translating, box-box (`b2TimeOfImpact`)",
    "BM_ToiTranslation/poly8_poly8": "time of impact, translating, 8-gons",
    "BM_ToiTranslation/circle_poly8": "time of impact, translating, circle-8-gon",
    "BM_ToiTranslation/capsule_poly8": "time of impact, translating, capsule-8-gon",
    "BM_ToiRotation/box_box": "time of impact, turning up to pi/2, box-box",
    "BM_ToiRotation/poly8_poly8": "time of impact, turning, 8-gons",
    "BM_ToiRotation/circle_poly8": "time of impact, turning, circle-8-gon",
    "BM_ToiRotation/capsule_poly8": "time of impact, turning, capsule-8-gon",
    "BM_ShapeCast_shuffled/box_box": "shape cast, box-box, shuffled",
    "BM_ShapeCast_shuffled/poly8_poly8": "shape cast, 8-gons, shuffled",
    "BM_ShapeCast_shuffled/circle_poly8": "shape cast, circle-8-gon, shuffled",
    "BM_ShapeCast_shuffled/capsule_poly8": "shape cast, capsule-8-gon, shuffled",
    "BM_ToiTranslation_shuffled/box_box": "time of impact, translating, box-box, shuffled",
    "BM_ToiTranslation_shuffled/poly8_poly8": "time of impact, translating, 8-gons, shuffled",
    "BM_ToiTranslation_shuffled/circle_poly8": "time of impact, translating, circle-8-gon, shuffled",
    "BM_ToiTranslation_shuffled/capsule_poly8": "time of impact, translating, capsule-8-gon, shuffled",
    "BM_ToiRotation_shuffled/box_box": "time of impact, turning, box-box, shuffled",
    "BM_ToiRotation_shuffled/poly8_poly8": "time of impact, turning, 8-gons, shuffled",
    "BM_ToiRotation_shuffled/circle_poly8": "time of impact, turning, circle-8-gon, shuffled",
    "BM_ToiRotation_shuffled/capsule_poly8": "time of impact, turning, capsule-8-gon, shuffled",
}
ACCURACY = ("sep_at_t", "overlap", "hit_rate")
# Queries collide answers with a batched call that the rivals do not have: their rows borrow
# the rivals of the one-call-per-pair query on the same pairs in the same order.
RIVALS_FROM = {
    "BM_Contact_CirclePoly_batch/1024": "BM_Contact_CirclePoly/1024",
    "BM_Contact_CirclePoly_batch/64": "BM_Contact_CirclePoly/64",
    "BM_Contact_CirclePoly_batch_shuffled/1024": "BM_Contact_CirclePoly_shuffled/1024",
    "BM_Contact_CirclePoly_batch_shuffled/64": "BM_Contact_CirclePoly_shuffled/64",
}


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
    known = [q for q in LABELS if q in table]
    for query in known + sorted(q for q in order if q not in LABELS):
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

        rivals = table.get(RIVALS_FROM.get(query, query), {})
        v3 = rivals.get("box2d_v3")
        old = rivals.get("box2d")
        print(f"| {LABELS.get(query, query)} | {cell(ours)} | {cell(v3)} | {cell(old)} | {ratio(v3)} | {ratio(old)} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
