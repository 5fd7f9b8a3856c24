"""The paper's performance and memory models, in code, fed with pvrt's own measurements.

Time of a render on P workers (ranks or threads):

    T(P) = tau_f * W / P + T_idle(P) + T_comm(P)

* tau_f: seconds per unit of work, from a serial run: its render time over its work count W (rays + intersection
  tests + shading operations, the deterministic count `--stats` prints per worker and `--load-map` per pixel).
* T_idle: what the busiest worker adds over the mean, tau_f * (max_p W_p - W / P), where W_p is the worker's share
  of the measured per-pixel work map under the strategy (block, cyclic, tiles; OpenMP's chunked schedules by list
  scheduling of their rows).
* T_comm: collecting the image on rank 0 from a ping-pong's latency tau_s and seconds per byte tau_b:
  MPI_Gatherv (P - 1) tau_s + tau_b B (P - 1) / P, recursive doubling ceil(log2 P) tau_s + tau_b B (P - 1) / P,
  B = bytes of the image in flight (pvrt sends 3 bytes a pixel for a PNG or TGA, as sRGB; 12 for an EXR;
  4 more with a load map). OpenMP: 0.

Memory (the paper's formulas, bytes over all ranks): L lights of 24 bytes and B balls of 96 bytes in every rank,
plus the image: recursive doubling 3XY (1 + log2(P) / 2), MPI_Gather 6XY.
"""
import math

import numpy as np


def ping_pong_costs(rows):
    """(tau_s, tau_b) from `pvrt mpi-bench` CSV rows: tau_s the one-way time of an empty message, tau_b the
    least-squares slope of one-way time against bytes over messages of 64 KiB and more. Both from the fastest of
    the repetitions: the wire's and the library's cost; on a shared machine the median also holds the time
    slices other programs take from a rank that waits by polling (20 ms medians were seen under load 13)."""
    pp = [r for r in rows if r["test"] == "pingpong-one-way"]
    empty = [float(r["min_us"]) for r in pp if int(r["bytes"]) == 0]
    big = [(int(r["bytes"]), float(r["min_us"])) for r in pp if int(r["bytes"]) >= 65536]
    if not empty or len(big) < 2:
        raise ValueError("mpi-bench gave no ping-pong of 0 bytes and of two sizes >= 64 KiB")
    tau_s = empty[0] * 1e-6
    x = np.array([b for b, _ in big], float)
    y = np.array([t for _, t in big]) * 1e-6
    slope = float(np.polyfit(x, y, 1)[0])
    return tau_s, max(slope, 1e-12)


def rank_work(work, strategy, p, tile=32):
    """Each of p workers' share of the per-pixel work map (height x width) under a static strategy, the cut
    pvrt makes (src/parallel/schedule.cpp): block = rows [H w / p, H (w+1) / p), cyclic = row y to y mod p,
    tiles = tile i (row-major, tile x tile pixels) to i mod p."""
    h, w = work.shape
    rows = work.sum(axis=1)
    if strategy == "block":
        edges = [h * k // p for k in range(p + 1)]
        return np.array([rows[edges[k]:edges[k + 1]].sum() for k in range(p)])
    if strategy == "cyclic":
        return np.bincount(np.arange(h) % p, weights=rows, minlength=p)
    if strategy == "tiles":
        sums = tile_sums(work, tile).ravel()
        return np.bincount(np.arange(sums.size) % p, weights=sums, minlength=p)
    raise ValueError("no static split for " + strategy)


def tile_sums(work, tile):
    """Work of every tile x tile tile (edge tiles smaller), shape (tiles down, tiles across)."""
    h, w = work.shape
    th, tw = -(-h // tile), -(-w // tile)
    padded = np.zeros((th * tile, tw * tile))
    padded[:h, :w] = work
    return padded.reshape(th, tile, tw, tile).sum(axis=(1, 3))


def list_schedule(items, p, speed=None, overhead=0.0):
    """Finish time of items (work in seconds, in order) handed to whichever of p workers is free first, each item
    costing `overhead` more (a request): OpenMP's dynamic schedule, or a master's queue without its messages.
    speed[k] divides worker k's rate (1 = full speed)."""
    import heapq
    speed = speed if speed is not None else [1.0] * p
    free = [(0.0, k) for k in range(p)]
    heapq.heapify(free)
    for t in items:
        at, k = heapq.heappop(free)
        heapq.heappush(free, (at + overhead + t * speed[k], k))
    return max(at for at, _ in free)


def openmp_chunks(work, schedule, chunk, p):
    """Row chunks of OpenMP's schedules, in the order they are handed out: static (round robin, chunk 0 = one block
    per thread), dynamic (chunk 0 = 1), guided (chunks of remaining / p, at least chunk)."""
    rows = work.sum(axis=1)
    h = len(rows)
    out = []
    if schedule == "guided":
        y, least = 0, max(1, chunk)
        while y < h:
            n = max(least, -(-(h - y) // p))
            out.append(rows[y:y + n].sum())
            y += n
        return out
    n = chunk if chunk > 0 else (1 if schedule == "dynamic" else -(-h // p))
    return [rows[y:y + n].sum() for y in range(0, h, n)]


def openmp_time_units(work, schedule, chunk, p):
    """The busiest thread's work under an OpenMP row schedule (static deals chunks round robin; dynamic and
    guided go to the first free thread)."""
    chunks = openmp_chunks(work, schedule, chunk, p)
    if schedule == "static":
        return max(sum(chunks[k::p]) for k in range(p))
    return list_schedule(chunks, p)


def gather_seconds(kind, p, pixels, tau_s, tau_b, bytes_per_pixel=3):
    if p <= 1:
        return 0.0
    volume = tau_b * pixels * bytes_per_pixel * (p - 1) / p
    hops = (p - 1) if kind == "gather" else math.ceil(math.log2(p))
    return hops * tau_s + volume


def predict(work_share, total_work, p, tau_f, comm=0.0):
    """Predicted render seconds and its parts from each worker's share of the work (fractions summing to 1)."""
    share = np.asarray(work_share, float)
    share = share / share.sum()
    compute = tau_f * total_work / p
    idle = tau_f * total_work * (share.max() - 1.0 / p)
    return dict(pred_s=compute + idle + comm, pred_compute_s=compute, pred_idle_s=idle, pred_comm_s=comm)


def paper_memory(lights, balls, p, x, y, gather):
    """The paper's bytes over all ranks: (24L + 96B)P + image (recursive doubling 3XY(1 + log2(P)/2), gather 6XY)."""
    scene = (24 * lights + 96 * balls) * p
    image = 3 * x * y * (1 + math.log2(p) / 2) if gather == "recursive-doubling" else 6 * x * y
    return scene + image


def slope(xs, ys):
    """Least-squares slope and intercept of ys against xs (None when fewer than two distinct xs)."""
    if len(set(xs)) < 2:
        return None, None
    k, c = np.polyfit(np.array(xs, float), np.array(ys, float), 1)
    return float(k), float(c)
