"""Table 1: pvrt built by each compiler and optimisation level, each in its own folder (only the `pvrt` target,
through ccache when there is one), then timed on scene 1 at c = 16 with OpenMP on every core. The binary that
runs the rest of the report is timed beside them as it was built (its CMake build type and compiler)."""
import os
import re
import shutil
import statistics
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def build(a, name):
    """Configures and builds OUT/builds/<name>/pvrt; returns (path or None, seconds, log)."""
    compiler, flags = name.split(" ", 1)
    folder = os.path.join(a.out, "builds", re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_"))
    os.makedirs(folder, exist_ok=True)
    log = os.path.join(folder, "build.log")
    cfg = ["cmake", "-S", ROOT, "-B", folder, "-DCMAKE_BUILD_TYPE=None", "-DCMAKE_CXX_COMPILER=" + compiler,
           "-DCMAKE_CXX_FLAGS=%s -DNDEBUG" % flags]
    if compiler.startswith("clang"):
        cfg.append("-DCMAKE_C_COMPILER=" + compiler.replace("clang++", "clang"))
    if shutil.which("ccache"):
        cfg += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
    env = dict(os.environ, CCACHE_BASEDIR=os.path.dirname(ROOT))
    started = time.time()
    with open(log, "w") as out:
        ok = subprocess.run(cfg, stdout=out, stderr=subprocess.STDOUT, env=env).returncode == 0 and \
            subprocess.run(["cmake", "--build", folder, "--target", "pvrt", "-j", str(a.max_p)], stdout=out,
                           stderr=subprocess.STDOUT, env=env).returncode == 0
    binary = os.path.join(folder, "pvrt")
    return (binary if ok and os.path.exists(binary) else None), time.time() - started, log


def this_build(a):
    """How the report's own binary was built, from its CMake cache."""
    cache = os.path.join(os.path.dirname(a.pvrt), "CMakeCache.txt")
    try:
        text = open(cache).read()
    except OSError:
        return "the given binary"
    get = lambda k: (re.search(r"^%s:[A-Z]+=(.*)$" % k, text, re.M) or [None, "?"])[1]  # noqa: E731
    return "this build (%s, CMAKE_BUILD_TYPE=%s)" % (os.path.basename(get("CMAKE_CXX_COMPILER")),
                                                     get("CMAKE_BUILD_TYPE"))


def table1(a, r):
    size = (1280, 800)
    rows = []
    builds = [(this_build(a), a.pvrt, None)]
    for name in a.compilers:
        binary, secs, log = build(a, name)
        builds.append((name, binary, secs))
        print("  table1 build %-24s %s in %.0f s" % (name, "ok" if binary else "FAILED (%s)" % log, secs), flush=True)
    for name, binary, secs in builds:
        times = []
        for rep in range(a.reps if binary else 0):
            row = r.render("table1", "scene1", 16 if a.mode != "quick" else 4, a.max_p, strategy="tiles", rep=rep,
                           size=size if a.mode != "quick" else (a.width, a.height), pvrt=binary, note=name)
            if "render_s" in row:
                times.append(row["render_s"])
        rows.append(dict(build=name, build_s=secs, status="ok" if times else "build failed",
                         render_s=statistics.median(times) if times else None,
                         render_min_s=min(times) if times else None, render_max_s=max(times) if times else None))
    return rows
