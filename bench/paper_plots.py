"""The report's figures (matplotlib, Agg) and the small tables they share with the Markdown."""
import os

import numpy as np

import model


def ratios(meds):
    """(scene, backend, P, T_block, T_cyclic) of fig. 9."""
    t = {(m["scene"], m["backend"], m["strategy"], m["p"]): m["render_s"] for m in meds if m["figure"] == "fig9"}
    out = []
    for (scene, backend, strategy, p), tc in sorted(t.items()):
        if strategy == "cyclic" and (scene, backend, "block", p) in t:
            out.append((scene, backend, p, t[(scene, backend, "block", p)], tc))
    return out


def fig13_slopes(meds):
    out = {}
    for backend in ("openmp", "mpi"):
        xs = [(m["p"], m["render_s"]) for m in meds if m["figure"] == "fig13" and m["backend"] == backend]
        k, c = model.slope([p for p, _ in xs], [t for _, t in xs])
        if k is not None:
            out[backend] = (k, c)
    return out


def gather_table(rows):
    """(P, bytes per pixel, gatherv, recursive doubling, note) of the 1280x800 rows."""
    cell = {}
    for x in rows:
        if x["image"] == "1280x800" and x["test"].startswith("gather-"):
            cell[(int(x["ranks"]), int(x["bytes_per_pixel"]), x["test"])] = (
                "%.0f [%.0f–%.0f]" % (float(x["median_us"]), float(x["min_us"]), float(x["max_us"])),
                x.get("oversubscribed"))
    out = []
    for p, bpp in sorted({(p, b) for p, b, _ in cell}):
        g = cell.get((p, bpp, "gather-gatherv"), ("–", ""))
        rd = cell.get((p, bpp, "gather-recursive-dbl"), ("–", ""))
        out.append((p, bpp, g[0], rd[0], "more ranks than cores" if g[1] or rd[1] else ""))
    return out


def all_plots(a, ctx, res):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    out = a.out

    def save(fig, name):
        fig.tight_layout()
        fig.savefig(os.path.join(out, name), dpi=100)
        plt.close(fig)

    for fig_no, scene in (("4", "scene1"), ("5", "scene2")):
        fig, ax = plt.subplots(figsize=(7, 4.6))
        m = res["maps"].get((scene, 8))
        if m is not None:
            im = ax.imshow(np.maximum(m, 1), norm=LogNorm(), cmap="inferno")
            fig.colorbar(im, ax=ax, label="work per pixel (rays + tests + shading ops), log scale")
        ax.set_title("fig. %s: load map, %s, c = 8" % (fig_no, scene))
        save(fig, "fig%s_loadmap_%s.png" % (fig_no, scene))

    meds = res["medians"]
    serial = {m["scene"]: m["render_s"] for m in meds if m["figure"] == "serial"}
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for backend, style in (("openmp", "o-"), ("mpi", "s--")):
        xs = sorted((m["p"], m["render_s"]) for m in meds if m["figure"] == "fig9" and m["scene"] == "scene1"
                    and m["backend"] == backend and m["strategy"] == "cyclic")
        if xs and "scene1" in serial:
            ax.plot([p for p, _ in xs], [serial["scene1"] / t for _, t in xs], style, label=backend + " cyclic")
            ax2.plot([p for p, _ in xs], [100 * serial["scene1"] / t / p for p, t in xs], style, label=backend)
    ax.plot([1, a.max_p], [1, a.max_p], "k:", label="ideal")
    ax.set(xlabel="P", ylabel="speedup", title="fig. 6: speedup, scene 1, c = 16")
    ax2.set(xlabel="P", ylabel="efficiency %", ylim=(0, 110), title="fig. 6: efficiency")
    ax.legend()
    save(fig, "fig6_speedup.png")

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, scene in zip(axes, ("scene1", "scene2")):
        for k, x in enumerate(r for r in res["fig78"] if r["scene"] == scene):
            ax.bar(np.arange(8) + (k - 0.5) * 0.4, x["measured"], 0.4, label=x["strategy"])
        ax.set(xlabel="rank", ylabel="work", title="figs. 7/8: %s, 8 ranks, c = 8" % scene)
        ax.legend()
    save(fig, "fig7_8_loads.png")

    fig, ax = plt.subplots(figsize=(7, 4))
    for scene in ("scene1", "scene2"):
        for backend, style in (("openmp", "o-"), ("mpi", "s--")):
            xs = [(p, tb / tc) for s, b, p, tb, tc in ratios(meds) if s == scene and b == backend]
            if xs:
                ax.plot([p for p, _ in xs], [v for _, v in xs], style, label="%s %s" % (scene, backend))
    ax.axhline(1, color="k", lw=0.5)
    ax.set(xlabel="P", ylabel="r_S = S_cyclic / S_block", title="fig. 9")
    ax.legend()
    save(fig, "fig9_ratio.png")

    imgs = [(c, plt.imread(p)) for c, p in ctx["fig10"] if os.path.exists(p)]
    fig, axes = plt.subplots(2, max(1, len(imgs)), figsize=(4 * max(1, len(imgs)), 5.5), squeeze=False)
    for k, (c, im) in enumerate(imgs):
        h, w = im.shape[:2]
        axes[0][k].imshow(im)
        axes[0][k].set_title("c = %d" % c)
        y0, x0 = int(h * 0.45), int(w * 0.45)
        axes[1][k].imshow(im[y0:y0 + max(4, h // 8), x0:x0 + max(4, w // 8)], interpolation="nearest")
        axes[1][k].set_title("crop (1/8 of each side), c = %d" % c)
        for ax in (axes[0][k], axes[1][k]):
            ax.axis("off")
    save(fig, "fig10_images.png")

    fig, ax = plt.subplots(figsize=(7, 4))
    rows = ctx["bench"]["rows"]
    for test, bpp, style in (("gather-gatherv", 3, "o-"), ("gather-recursive-dbl", 3, "s-"),
                             ("gather-gatherv", 12, "o--"), ("gather-recursive-dbl", 12, "s--")):
        xs = sorted((int(x["ranks"]), float(x["median_us"]), float(x["min_us"]), float(x["max_us"])) for x in rows
                    if x["test"] == test and int(x["bytes_per_pixel"]) == bpp and x["image"] == "1280x800")
        if xs:
            p = np.array([x[0] for x in xs])
            med = np.array([x[1] for x in xs])
            err = [med - [x[2] for x in xs], [x[3] for x in xs] - med]
            ax.errorbar(p, med, yerr=err, fmt=style, capsize=3, label="%s, %d B/px" % (test[7:], bpp))
    ax.axvline(a.max_p + 0.5, color="grey", lw=0.5, ls=":")
    ax.set(xlabel="P (right of the dotted line: more ranks than cores)", ylabel="microseconds (median, min-max)",
           yscale="log", title="fig. 11: collecting a 1280x800 image")
    ax.legend(fontsize=8)
    save(fig, "fig11_gather.png")

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, scene in zip(axes, ("scene1", "scene2")):
        for sched, style in (("static", "o-"), ("dynamic", "s-"), ("guided", "^-")):
            xs = sorted((int(m["chunk"]), m["render_s"]) for m in meds if m["figure"] == "fig12"
                        and m["scene"] == scene and m["strategy"] == sched)
            if xs:
                ax.plot([c for c, _ in xs], [t for _, t in xs], style, label=sched)
        ax.set(xscale="log", xlabel="chunk (rows)", ylabel="render s", title="fig. 12: %s, %d threads" % (
            scene, a.max_p))
        ax.legend()
    save(fig, "fig12_schedules.png")

    fig, ax = plt.subplots(figsize=(7, 4))
    for backend, style in (("openmp", "o"), ("mpi", "s")):
        xs = sorted((m["p"], m["render_s"]) for m in meds if m["figure"] == "fig13" and m["backend"] == backend)
        if xs:
            ax.plot([p for p, _ in xs], [t for _, t in xs], style, label=backend)
        k, c = fig13_slopes(meds).get(backend, (None, None))
        if k is not None:
            ps = np.array([1, a.max_p])
            ax.plot(ps, c + k * ps, "--", label="%s trend: %.4f s per P" % (backend, k))
    ax.set(xlabel="P", ylabel="render s", title="fig. 13: c/P = 8, scene 1", ylim=(0, None))
    ax.legend()
    save(fig, "fig13_constant.png")

    fig, ax = plt.subplots(figsize=(7, 4))
    for x in res["model"]:
        ax.plot(x["measured_s"], x["pred_s"], "o" if x["backend"] == "openmp" else "s",
                color={"fig9": "C0", "fig13": "C1", "sim": "C2"}[x["figure"]])
    lim = max([x["measured_s"] for x in res["model"]] + [x["pred_s"] for x in res["model"]] + [1e-3])
    ax.plot([0, lim], [0, lim], "k:")
    ax.set(xlabel="measured s", ylabel="predicted s", title="performance model (blue fig. 9, orange 13, green sim)")
    save(fig, "model_error.png")

    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    sim = res["sim"]
    for col, image in enumerate(sorted({r["image"] for r in sim["rows"]}) if sim else []):
        for row, f in enumerate((0.0, 0.25)):
            ax = axes[row][col]
            series = {}
            for r in sim["rows"]:
                if r["image"] == image and r["slow_fraction"] == f:
                    series.setdefault((r["strategy"], r["tile"]), []).append((r["ranks"], r["efficiency"]))
            for (strategy, tile), xs in sorted(series.items(), key=lambda kv: tuple(map(str, kv[0]))):
                ax.plot([p for p, _ in xs], [e for _, e in xs], "-" if strategy in ("tiles", "dynamic") else "-o",
                        label="%s %s" % (strategy, tile), lw=1)
            ax.set(xscale="log", xlabel="ranks", ylabel="efficiency", ylim=(0, 1.05),
                   title="%s, %s" % (image, "homogeneous" if f == 0 else "a quarter of ranks 2x slower"))
            ax.axhline(0.5, color="grey", lw=0.5, ls=":")
            ax.legend(fontsize=6, ncol=2)
    save(fig, "sim_efficiency.png")

    fig, ax = plt.subplots(figsize=(7, 4))
    mem = [x for x in res["memory"]["rows"] if x["kind"] == "pixels" and x["peak_rss_kib"]]
    for gather in ("none", "gather", "recursive-doubling"):
        for ranks in sorted({x["ranks"] for x in mem if x["gather"] == gather}):
            xs = sorted((x["pixels"], x["peak_rss_kib"] / 1024) for x in mem if x["gather"] == gather
                        and x["ranks"] == ranks and x["rank"] == 0)
            if xs:
                ax.plot([p for p, _ in xs], [v for _, v in xs], "o-", label="rank 0, %s, P=%d" % (gather, ranks))
    ax.set(xlabel="pixels", ylabel="peak RSS MiB", title="memory: rank 0's peak against the image")
    ax.legend(fontsize=7)
    save(fig, "memory.png")
