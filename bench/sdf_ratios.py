#!/usr/bin/env python3
"""Tables and ratios of a bench_sdf run, from its JSON output (the medians of the repetitions).

    build/release/bench/bench_sdf --benchmark_enable_random_interleaving=true \\
        --benchmark_repetitions=5 --benchmark_out=sdf.json --benchmark_out_format=json
    python3 bench/sdf_ratios.py sdf.json

Prints Markdown: build times at the 4M voxel with the ratios (exact / dense: the target is 10x;
OpenVDB / collide), memory against voxel size, errors (world units and voxels), query times per
point with their ratio to the bare array read (target: within 2x) and OpenVDB's to collide's, and
particle steps (target: under 5 ns).
"""

import json
import statistics
import sys
from collections import defaultdict

MAIN = "4M"
SCALES = ["64k", "512k", "4M", "32M"]
BUILDS = ["collide_dense", "collide_sparse", "collide_exact", "openvdb", "openvdb_2t", "openvdb_wide"]
SAMPLES = ["bare_read", "bare_lookup", "dense_inside", "dense_sample", "dense_sample_batch", "dense_gradient", "sparse_inside",
           "sparse_sample", "openvdb_point", "openvdb_box"]
TO_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def load(path):
    """run name -> {field: median}, from the repetitions (or from the median aggregate alone)."""
    with open(path) as f:
        data = json.load(f)
    runs = defaultdict(list)
    medians = {}
    for b in data["benchmarks"]:
        # "BM_SdfBuild/torus/4M/collide_exact/iterations:1/real_time" -> ".../collide_exact"
        name = "/".join(part for part in b.get("run_name", b["name"]).split("/")
                        if part != "real_time" and not part.startswith(("iterations:", "repeats:")))
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") == "median":
                medians[name] = b
        else:
            runs[name].append(b)
    out = {}
    for name in set(runs) | set(medians):
        if runs.get(name):
            fields = {}
            for key, value in runs[name][0].items():
                if isinstance(value, (int, float)) and not isinstance(value, bool):
                    fields[key] = statistics.median(r[key] for r in runs[name] if key in r)
            fields["time_unit"] = runs[name][0]["time_unit"]
            fields["repetitions"] = len(runs[name])
        else:
            fields = dict(medians[name])
        fields["real_ns"] = fields["real_time"] * TO_NS[fields["time_unit"]]
        fields["cpu_ns"] = fields["cpu_time"] * TO_NS[fields["time_unit"]]
        out[name] = fields
    return data.get("context", {}), out


def fmt_ms(ns):
    return "-" if ns is None else (f"{ns / 1e6:.1f} ms" if ns >= 1e7 else f"{ns / 1e6:.2f} ms")


def fmt_mb(b):
    return "-" if b is None else f"{b / 2**20:.2f} MB" if b < 10 * 2**20 else f"{b / 2**20:.0f} MB"


def ratio(a, b):
    return "-" if a is None or b is None or b == 0 else f"{a / b:.2f}x"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    context, runs = load(sys.argv[1])
    meshes = []
    for name in runs:
        parts = name.split("/")
        if parts[0].startswith("BM_Sdf") and parts[1] not in meshes:
            meshes.append(parts[1])
    meshes.sort()

    def get(name, key):
        r = runs.get(name)
        return None if r is None else r.get(key)

    for key in context:
        if key.startswith(("collide", "openvdb", "threads", "mesh")):
            print(f"- {key}: {context[key]}")
    print()

    print(f"### Build at the {MAIN} voxel (median wall time)\n")
    print("| mesh | nodes | dense | sparse | exact (BVH) | OpenVDB narrow 1 thread / 2 | OpenVDB wide | "
          "exact / dense | OpenVDB / sparse | OpenVDB wide / dense |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for m in meshes:
        t = {lib: get(f"BM_SdfBuild/{m}/{MAIN}/{lib}", "real_ns") for lib in BUILDS}
        nodes = get(f"BM_SdfBuild/{m}/{MAIN}/collide_dense", "nodes")
        if nodes is None:
            continue
        print(f"| {m} | {nodes / 1e6:.2f}M | {fmt_ms(t['collide_dense'])} | {fmt_ms(t['collide_sparse'])} | "
              f"{fmt_ms(t['collide_exact'])} | {fmt_ms(t['openvdb'])} / {fmt_ms(t['openvdb_2t'])} | "
              f"{fmt_ms(t['openvdb_wide'])} | {ratio(t['collide_exact'], t['collide_dense'])} | "
              f"{ratio(t['openvdb'], t['collide_sparse'])} | {ratio(t['openvdb_wide'], t['collide_dense'])} |")
    print()

    print("### Memory and build time against voxel size\n")
    print("| mesh | nodes (voxel) | dense (distances alone) | sparse | OpenVDB level set | OpenVDB wide | "
          "build dense / sparse / OpenVDB |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for m in meshes:
        for s in SCALES:
            d = f"BM_SdfBuild/{m}/{s}/collide_dense"
            if d not in runs:
                continue
            print(f"| {m} | {get(d, 'nodes') / 1e6:.2f}M ({get(d, 'voxel'):.3g}) | {fmt_mb(get(d, 'bytes'))} "
                  f"({fmt_mb(get(d, 'distance_bytes'))}) | {fmt_mb(get(f'BM_SdfBuild/{m}/{s}/collide_sparse', 'bytes'))} | "
                  f"{fmt_mb(get(f'BM_SdfBuild/{m}/{s}/openvdb', 'bytes'))} | "
                  f"{fmt_mb(get(f'BM_SdfBuild/{m}/{s}/openvdb_wide', 'bytes'))} | "
                  f"{fmt_ms(get(d, 'real_ns'))} / {fmt_ms(get(f'BM_SdfBuild/{m}/{s}/collide_sparse', 'real_ns'))} / "
                  f"{fmt_ms(get(f'BM_SdfBuild/{m}/{s}/openvdb', 'real_ns'))} |")
    print()

    print(f"### Error against the exact distance at the {MAIN} voxel (world units; voxels in brackets)\n")
    print("| mesh | field | band max | band mean | everywhere max | everywhere mean | sign agrees |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for m in meshes:
        for lib in ["collide_dense", "collide_sparse", "collide_exact", "openvdb", "openvdb_wide"]:
            n = f"BM_SdfBuild/{m}/{MAIN}/{lib}"
            if n not in runs:
                continue
            v = get(n, "voxel")

            def e(key):
                x = get(n, key)
                return "-" if x is None else f"{x:.3g} ({x / v:.2f})"

            print(f"| {m} | {lib} | {e('band_max_err')} | {e('band_mean_err')} | {e('all_max_err')} | "
                  f"{e('all_mean_err')} | {100 * get(n, 'sign_agree'):.2f}% |")
    print()

    print(f"### Queries at the {MAIN} voxel (ns per point; ratio to bare_read in brackets)\n")
    print("| mesh / points | " + " | ".join(SAMPLES) + " | OpenVDB box / dense sample | "
          "OpenVDB point / dense inside |")
    print("| --- " * (len(SAMPLES) + 3) + "|")
    for m in meshes:
        for pts in ["box", "band"]:
            ns = {s: get(f"BM_SdfSample/{m}/{MAIN}/{pts}/{s}", "per_point") for s in SAMPLES}
            ns = {s: None if v is None else v * 1e9 for s, v in ns.items()}
            base = ns["bare_read"]
            if base is None:
                continue
            cells = [("-" if ns[s] is None else f"{ns[s]:.2f} ({ns[s] / base:.2f})") for s in SAMPLES]
            print(f"| {m} / {pts} | " + " | ".join(cells) +
                  f" | {ratio(ns['openvdb_box'], ns['dense_sample'])} | {ratio(ns['openvdb_point'], ns['dense_inside'])} |")
    print()

    print(f"### Queries against a bare read at a point (bare_lookup: the index computed from the point)\n")
    print("| mesh / points | bare_lookup ns | dense_inside | dense_sample | dense_sample_batch | sparse_inside | sparse_sample |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for m in meshes:
        for pts in ["box", "band"]:
            ns = {s: get(f"BM_SdfSample/{m}/{MAIN}/{pts}/{s}", "per_point") for s in SAMPLES}
            base = ns["bare_lookup"]
            if base is None:
                continue
            cells = [ratio(ns[s], base) for s in ["dense_inside", "dense_sample", "dense_sample_batch", "sparse_inside",
                                                  "sparse_sample"]]
            print(f"| {m} / {pts} | {base * 1e9:.2f} | " + " | ".join(cells) + " |")
    print()

    print(f"### Closest points at the {MAIN} voxel: stored field vs gradient steps vs exact (BVH)\n")
    print("| mesh / points | method | ns per point | off the surface, max / mean (voxels) | "
          "farther than the nearest, max / mean (voxels) |")
    print("| --- | --- | --- | --- | --- |")
    for m in meshes:
        for pts in ["box", "band"]:
            for method in ["stored", "gradient_1", "gradient_2", "bvh_nearest"]:
                n = f"BM_SdfClosest/{m}/{MAIN}/{pts}/{method}"
                if n not in runs:
                    continue
                v = get(n, "voxel")
                print(f"| {m} / {pts} | {method} | {get(n, 'per_point') * 1e9:.1f} | "
                      f"{get(n, 'off_max') / v:.2f} / {get(n, 'off_mean') / v:.3f} | "
                      f"{get(n, 'excess_max') / v:.2f} / {get(n, 'excess_mean') / v:.3f} |")
    print()

    print(f"### Particles (step_particles, {MAIN} voxel)\n")
    print("| mesh | field | ns per particle step | bounced | near (sampled) |")
    print("| --- | --- | --- | --- | --- |")
    for m in meshes:
        for f in ["dense", "sparse", "dense_sorted", "sparse_sorted"]:
            n = f"BM_SdfParticles/{m}/{MAIN}/{f}"
            if n in runs:
                print(f"| {m} | {f} | {get(n, 'per_step') * 1e9:.2f} | {100 * get(n, 'bounced'):.2f}% | "
                      f"{100 * get(n, 'near'):.1f}% |")


if __name__ == "__main__":
    main()
