"""The figures of `pvrt render --stats-json FILE` (docs/cli.md), flattened for the benchmark tables.

Every script in bench/ asks pvrt for its statistics as JSON and reads them here, instead of matching
the text of `--stats` with regular expressions.
"""
import json
import statistics


def read(path_or_text):
    """The JSON object pvrt wrote (a file name, or the text itself); {} when there is none or it is not JSON."""
    try:
        if path_or_text.lstrip().startswith("{"):
            return json.loads(path_or_text)
        with open(path_or_text) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def figures(st):
    """One flat dict: stage times, BVH, ray counts, per-worker or per-rank figures (only those present)."""
    r = {}
    if not st:
        return r
    sec = st.get("seconds", {})
    for key in ("load", "build", "render", "write"):
        if key in sec:
            r[key + "_s"] = sec[key]
    for key, cpu in st.get("cpu_seconds", {}).items():
        r[key + "_cpu_s"] = cpu
    bvh = st.get("bvh", {})
    if bvh:
        r.update(bvh_nodes=bvh["nodes"], bvh_kib=bvh["bytes"] / 1024.0, bvh_build_s=bvh["build_seconds"])
    r["structures_kib"] = (bvh.get("bytes", 0) + st.get("light_buffers", {}).get("bytes", 0)) / 1024.0
    counts = st.get("counts", {})
    for key in ("primary_rays", "vista_rays", "shadow_rays", "reflected_rays", "refracted_rays", "transmitted_rays", "total_rays",
                "intersection_tests"):
        if key in counts:
            r[key] = counts[key]
    if r.get("render_s") and r.get("total_rays"):
        r["rays_per_s"] = r["total_rays"] / r["render_s"]
    workers = st.get("workers")
    ranks = st.get("ranks")
    if ranks:
        compute = [k["compute_seconds"] for k in ranks if k["pixels"] > 0]
        if compute:
            r.update(rank_compute_min_s=min(compute), rank_compute_max_s=max(compute),
                     rank_compute_mean_s=statistics.mean(compute))
        r["rank_comm_max_s"] = max(k["comm_seconds"] for k in ranks)
        r["rank_idle_max_s"] = max(k["idle_seconds"] for k in ranks)
        r["imbalance_work"] = st["imbalance"]["work"]
        r["worker_work"] = [k["work"] for k in ranks]
        r["worker_seconds"] = [k["compute_seconds"] for k in ranks]
    elif workers:
        r["worker_work"] = [w["work"] for w in workers]
        r["worker_seconds"] = [w["seconds"] for w in workers]
    return r
