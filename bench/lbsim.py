"""A load-balance simulator: pvrt's MPI strategies on P = 1 .. 4096 ranks, from a measured per-pixel work map and
measured costs (tau_f seconds per work unit, tau_s message latency, tau_b seconds per byte; bench/model.py).

* block, cyclic, tiles (any size, dealt round robin): every rank renders its share, then the image is collected
  by recursive doubling (bench/model.py's gather_seconds). T = max over ranks of tau_f W_r k_r + T_gather.
* dynamic (master/worker, pvrt's default): tiles handed out in row-major order to whichever rank asks first.
  A worker's request reaches rank 0 after tau_s; rank 0 answers requests one at a time, tau_s each, and the
  answer takes tau_s back; rank 0 renders tiles too and pays for its answers in its own time. Workers do not ask
  ahead (pvrt's ranks do, so the simulator's dynamic is the cautious side), then the same gather.

Heterogeneous ranks: the last ceil(f P) ranks are k times slower (their work costs k tau_f). Speedup is against
one full-speed rank (tau_f W); efficiency is speedup over the ranks' capacity (P - n_slow + n_slow / k).
"""
import heapq
import math

import numpy as np

import model


def slow_factors(p, f=0.0, k=1.0):
    n_slow = int(math.ceil(f * p)) if f > 0 and k != 1 else 0
    return np.array([1.0] * (p - n_slow) + [float(k)] * n_slow), n_slow


def dynamic_finish(tiles, p, tau_f, tau_s, slow):
    """Finish time of the master/worker schedule of tiles (work units, in order) on p ranks."""
    if p == 1:
        return tau_f * float(np.sum(tiles)) * slow[0]
    ready = [(0.0, r) for r in range(p)]
    heapq.heapify(ready)
    master_free = 0.0   # when rank 0 can answer the next request
    master_debt = 0.0   # answering time rank 0 has not yet paid in its own rendering
    finish = np.zeros(p)
    for w in tiles:
        t, r = heapq.heappop(ready)
        if r == 0:
            start = t + master_debt
            master_debt = 0.0
        else:
            serve = max(t + tau_s, master_free)
            master_free = serve + tau_s
            master_debt += tau_s
            start = serve + 2 * tau_s
        end = start + tau_f * w * slow[r]
        finish[r] = end
        heapq.heappush(ready, (end, r))
    finish[0] += master_debt
    return float(finish.max())


class Image:
    """A work map with its row and tile sums kept (an 8K map is 33 million pixels: sum them once)."""

    def __init__(self, work):
        self.shape, self.size, self.total = work.shape, work.size, float(work.sum())
        self.rows = work.sum(axis=1)
        self._work, self._tiles = work, {}

    def tiles(self, tile):
        if tile not in self._tiles:
            self._tiles[tile] = model.tile_sums(self._work, tile).ravel()
        return self._tiles[tile]

    def rank_work(self, strategy, p, tile):
        h = len(self.rows)
        if strategy == "block":
            edges = np.array([h * k // p for k in range(p + 1)])
            c = np.concatenate([[0.0], np.cumsum(self.rows)])
            return c[edges[1:]] - c[edges[:-1]]
        source = self.rows if strategy == "cyclic" else self.tiles(tile)
        return np.bincount(np.arange(source.size) % p, weights=source, minlength=p)


def simulate(work, strategy, p, tau_f, tau_s, tau_b, tile=32, f=0.0, k=1.0, bytes_per_pixel=3):
    """Predicted seconds, speedup and efficiency of one configuration (work: a map or an Image)."""
    img = work if isinstance(work, Image) else Image(work)
    slow, n_slow = slow_factors(p, f, k)
    total = img.total
    gather = model.gather_seconds("recursive-doubling", p, img.size, tau_s, tau_b, bytes_per_pixel)
    if strategy == "dynamic":
        t = dynamic_finish(img.tiles(tile), p, tau_f, tau_s, slow) + gather
    else:
        t = tau_f * float(np.max(img.rank_work(strategy, p, tile) * slow)) + gather
    t1 = tau_f * total
    capacity = p - n_slow + n_slow / k if k else p
    return dict(time_s=t, speedup=t1 / t, efficiency=t1 / t / capacity, slow_ranks=n_slow)


def sweep(work, label, ps, tau_f, tau_s, tau_b, tiles=(8, 16, 32, 64, 128), hetero=((0.0, 1.0),)):
    """Rows for every strategy, tile size, P and heterogeneity."""
    rows = []
    img = Image(work)
    configs = [("block", 0), ("cyclic", 0)] + [("tiles", t) for t in tiles] + [("dynamic", t) for t in tiles]
    for f, k in hetero:
        for strategy, t in configs:
            for p in ps:
                r = simulate(img, strategy, p, tau_f, tau_s, tau_b, tile=t or 32, f=f, k=k)
                rows.append(dict(image=label, width=img.shape[1], height=img.shape[0], strategy=strategy,
                                 tile=t or "", ranks=p, slow_fraction=f, slow_factor=k, **r))
    return rows


def stops_scaling(rows, threshold=0.5):
    """For each (image, heterogeneity, strategy, tile): the largest P whose efficiency is still >= threshold."""
    out = {}
    for r in rows:
        key = (r["image"], r["slow_fraction"], r["slow_factor"], r["strategy"], r["tile"])
        if r["efficiency"] >= threshold:
            out[key] = max(out.get(key, 0), r["ranks"])
        else:
            out.setdefault(key, 0)
    return out


def best(rows, p):
    """For each (image, heterogeneity) the fastest (strategy, tile) at P ranks."""
    out = {}
    for r in rows:
        if r["ranks"] != p:
            continue
        key = (r["image"], r["slow_fraction"], r["slow_factor"])
        if key not in out or r["time_s"] < out[key]["time_s"]:
            out[key] = r
    return out
