#!/usr/bin/env bash
# Usage: stats_json.sh PVRT SCENE OUT_DIR
# --stats-json writes every figure --stats prints, as JSON, with the same values; to standard
# output with -; with the image, and not at all when the run fails.
set -euo pipefail
pvrt=$1 scene=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
"$pvrt" render "$scene" -W 64 -H 40 --spp 4 --threads 2 -o "$out/a.png" --stats --stats-json "$out/a.json" >"$out/a.txt"
python3 - "$out/a.json" "$out/a.txt" <<'PY' || fail "the JSON does not hold the figures of --stats"
import json, re, sys
j = json.load(open(sys.argv[1]))
text = open(sys.argv[2]).read()
assert j["format"] == "pvrt-stats 1", j["format"]
assert j["image"] == {"width": 64, "height": 40, "rays_per_pixel": 5, "sampler": "pov", "spp": 4}, j["image"]
assert j["backend"]["workers"] == 2 and len(j["workers"]) == 2, j["backend"]
for label, key in [("Primary rays", "primary_rays"), ("of them, by vista", "vista_rays"), ("Shadow rays", "shadow_rays"), ("Reflected rays", "reflected_rays"),
                   ("Total rays", "total_rays"), ("Intersection tests", "intersection_tests"),
                   ("Shading operations", "shading_operations")]:
    want = int(re.search(r"^\s*" + label + r"\s+(\d+)", text, re.M)[1])
    assert j["counts"][key] == want, (key, j["counts"][key], want)
assert j["counts"]["primary_rays"] == 64 * 40 * 5
assert sum(w["pixels"] for w in j["workers"]) == 64 * 40
assert sum(w["work"] for w in j["workers"]) == j["counts"]["work"]
m = re.search(r"Time\s+load ([\d.]+) s, build ([\d.]+) s, render ([\d.]+) s, write ([\d.]+) s", text)
for i, stage in enumerate(["load", "build", "render", "write"]):
    assert abs(j["seconds"][stage] - float(m[i + 1])) < 1e-4, (stage, j["seconds"][stage], m[i + 1])
m = re.search(r"CPU time\s+load ([\d.]+) s \(([\d.]+) cores\), build ([\d.]+) s \(([\d.]+)\), render ([\d.]+) s "
              r"\(([\d.]+)\), write ([\d.]+) s \(([\d.]+)\)", text)
assert m, "no CPU time line"
for i, stage in enumerate(["load", "build", "render", "write"]):
    cpu, cores = float(m[2 * i + 1]), float(m[2 * i + 2])
    assert abs(j["cpu_seconds"][stage] - cpu) < 1e-3, (stage, j["cpu_seconds"][stage], cpu)
    # CPU time is the process's: at most the 2 threads' worth of the stage's wall time, plus the clocks' grain
    # (the render's CPU time is taken around the renderer, whose own clock gives its wall time).
    assert cpu >= 0 and (stage == "render" or cores <= 2.2 or j["seconds"][stage] < 0.002), (stage, cpu, cores)
# Rendering 10,240 rays keeps a CPU busy for a good part of its wall time, even on a shared machine.
assert j["cpu_seconds"]["render"] > 0.2 * j["seconds"]["render"], (j["cpu_seconds"], j["seconds"])
m = re.search(r"BVH\s+(\d+) nodes, (\d+) leaves, depth (\d+)", text)
assert (j["bvh"]["nodes"], j["bvh"]["leaves"], j["bvh"]["depth"]) == tuple(map(int, m.groups())), j["bvh"]
assert j["kernel_effects"] in text
assert j["peak_memory_bytes"]["run"] >= j["peak_memory_bytes"]["after_load"] > 0
PY
# Standard output holds the JSON alone; a region and a time budget are in it.
"$pvrt" render "$scene" -W 64 -H 40 --start-col 2 --end-col 33 --time-budget 0.3 -o "$out/b.png" --quiet --stats-json - >"$out/b.json"
python3 - "$out/b.json" <<'PY' || fail "the JSON on standard output lacks the region or the budget"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["image"]["region"] == {"x0": 1, "y0": 0, "x1": 33, "y1": 40}, j["image"]
b = j["time_budget"]
assert b["method"] == "passes" and b["budget_seconds"] == 0.3, b
# Every pass traces every pixel of the region again.
assert sum(w["pixels"] for w in j["workers"]) == 32 * 40 * len(b["passes"])
assert b["passes"][0]["end_sample"] == 1 and b["chosen_spp"] == j["image"]["spp"] == b["passes"][-1]["end_sample"], b
PY
"$pvrt" render "$scene" -W 64 -H 40 --time-budget 0.3 --sampler jitter -o "$out/j.png" --quiet --stats-json - >"$out/j.json"
python3 - "$out/j.json" <<'PY' || fail "the JSON lacks the pilots of a budget with --sampler jitter"
import json, sys
j = json.load(open(sys.argv[1]))
assert sum(w["pixels"] for w in j["workers"]) == 64 * 40
b = j["time_budget"]
assert b["method"] == "pilots" and b["pilots"][0]["spp"] == 1 and b["chosen_spp"] == j["image"]["spp"], b
PY
# A run that fails writes neither the image nor the JSON.
echo '<scene><sphere radius="1"/></scene>' >"$out/bad.xml"
if "$pvrt" render "$out/bad.xml" -o "$out/c.png" --stats-json "$out/c.json" 2>/dev/null; then fail "a bad scene rendered"; fi
[ ! -e "$out/c.json" ] && [ ! -e "$out/c.png" ] || fail "a failed run left an output"
echo PASS
