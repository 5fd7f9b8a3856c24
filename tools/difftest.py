#!/usr/bin/env python3
"""Differential test against POV-Ray: random scenes of every shape, finish and light, built on round
numbers so that rays meet edges, faces and each other exactly, rendered by POV-Ray and by pvrt.

    tools/difftest.py --count 50 --seed 1 --out /tmp/difftest        # 50 scenes, seeds 1..50
    tools/difftest.py --count 20 --seed 7 --variant noaa --antialiasing=-A    # another antialiasing setting
    tools/difftest.py --count 20 --seed 7 --render-option=--pov-blocks       # pvrt in POV-Ray's block order

Each scene is written to OUT/scenes/diff_SEED.xml; `pvrt golden make` renders their exports with POV-Ray
(the references, OUT/scenes/reference/), `pvrt golden run` renders them with pvrt and compares. The summary
lists every scene that differs by more than one level in some channel, with its command to rerun; a seed
always gives the same scene, so a difference found once can be studied alone. Nothing here is tuned to
pass: the generator knows nothing of where pvrt and POV-Ray agree.
"""
import argparse
import os
import random
import re
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def vec(v):
    return " ".join(fmt(x) for x in v)


def fmt(x):
    return ("%d" % x) if float(x).is_integer() else ("%g" % x)


class SceneMaker:
    """One random scene from one seed: every choice from rng, every coordinate on a grid of halves."""

    def __init__(self, seed):
        self.r = random.Random(seed)
        self.lines = []
        self.materials = []

    def grid(self, lo, hi, step=0.5):
        return self.r.randint(int(lo / step), int(hi / step)) * step

    def point(self, lo=-3, hi=3, ylo=0, yhi=3):
        return (self.grid(lo, hi), self.grid(ylo, yhi), self.grid(lo, hi))

    def colour(self):
        return tuple(self.r.choice([0.2, 0.5, 0.8, 1.0]) for _ in range(3))

    def add(self, depth, text):
        self.lines.append("  " * depth + text)

    def camera(self):
        r = self.r
        loc = (self.grid(-6, 6, 1), self.grid(1, 6, 1), self.grid(-8, -3, 1))
        at = (self.grid(-1, 1), self.grid(0, 1.5), self.grid(-1, 1))
        attrs = 'location="%s" look_at="%s"' % (vec(loc), vec(at))
        if r.random() < 0.5:
            attrs += ' angle="%s"' % fmt(r.choice([30, 45, 60, 90]))
        attrs += ' right="1.6 0 0"'
        if r.random() < 0.1:  # straight down an axis, through edges
            attrs = 'location="0 %s 0" look_at="0 0 0" sky="0 0 1" right="1.6 0 0"' % fmt(self.grid(4, 8, 1))
        self.add(1, "<camera %s/>" % attrs)

    def lights(self):
        r = self.r
        for _ in range(r.randint(1, 3)):
            loc = (self.grid(-6, 6, 1), self.grid(3, 8, 1), self.grid(-6, 2, 1))
            colour = tuple(c * r.choice([0.5, 0.7, 1.0]) for c in (1, 1, 1))
            attrs = 'location="%s" color="%s"' % (vec(loc), vec(colour))
            if r.random() < 0.15:
                attrs += ' fade_distance="%s" fade_power="%s"' % (fmt(r.choice([2, 5])), fmt(r.choice([1, 2])))
            kind = r.random()
            if kind < 0.2:
                self.add(1, "<light_source %s>" % attrs)
                self.add(2, '<spotlight point_at="%s" radius="%s" falloff="%s" tightness="%s"/>' % (
                    vec(self.point(-1, 1, 0, 1)), fmt(r.choice([10, 20, 30])), fmt(r.choice([30, 40, 60])),
                    fmt(r.choice([0, 1, 10]))))
                self.add(1, "</light_source>")
            elif kind < 0.45:
                n = r.choice([2, 3])
                orient = r.random() < 0.15  # an oriented light is circular (POV-Ray makes it so)
                circular = orient or r.random() < 0.2
                self.add(1, "<light_source %s>" % attrs)
                self.add(2, '<area_light axis1="%s 0 0" axis2="0 0 %s" size1="%d" size2="%d" adaptive="%d"%s%s/>' % (
                    fmt(r.choice([1, 2])), fmt(r.choice([1, 2])), n, n, r.choice([0, 1, 100]),
                    ' circular="true"' if circular else "", ' orient="true"' if orient else ""))
                self.add(1, "</light_source>")
            else:
                self.add(1, "<light_source %s/>" % attrs)

    def material(self, depth):
        """An inline material: pigment, finish and interior as children."""
        r = self.r
        kind = r.choice(["matte", "matte", "shiny", "mirror", "glass", "checker", "metal"])
        if kind == "checker":
            self.add(depth, "<pigment>")
            self.add(depth + 1, '<checker color1="%s" color2="%s"/>' % (vec(self.colour()), vec(self.colour())))
            if r.random() < 0.5:
                self.add(depth + 1, '<scale v="%s"/>' % fmt(r.choice([0.5, 2])))
            self.add(depth, "</pigment>")
        elif kind == "glass":
            self.add(depth, '<pigment color="%s" filter="%s"/>' % (vec(self.colour()), fmt(r.choice([0.5, 0.9, 1]))))
        else:
            self.add(depth, '<pigment color="%s"/>' % vec(self.colour()))
        finish = []
        if kind == "shiny":
            finish.append('phong="%s" phong_size="%s"' % (fmt(r.choice([0.5, 1])), fmt(r.choice([20, 60]))))
        if kind == "mirror":
            finish.append('reflection="%s" diffuse="0.2"' % vec([r.choice([0.5, 0.9])] * 3))
        if kind == "metal":
            finish.append('specular="0.8" roughness="0.02" metallic="1" reflection="0.5 0.5 0.5"')
        if kind == "glass":
            finish.append('diffuse="0.1" phong="0.9" phong_size="120" reflection="0.1 0.1 0.1"')
        if r.random() < 0.2:
            finish.append('ambient="%s"' % vec([r.choice([0, 0.2])] * 3))
        if finish:
            self.add(depth, "<finish %s/>" % " ".join(finish))
        if kind == "glass":
            ior = r.choice([1.0, 1.33, 1.5, 2.0])
            fade = ' fade_distance="1" fade_power="2"' if r.random() < 0.2 else ""
            self.add(depth, '<interior ior="%s"%s/>' % (fmt(ior), fade))

    def transforms(self, depth):
        r = self.r
        for _ in range(r.choice([0, 0, 1, 2])):
            t = r.choice(["rotate", "rotate", "scale", "translate"])
            if t == "rotate":
                v = [r.choice([0, 0, 30, 45, 90, -45]) for _ in range(3)]
            elif t == "scale":
                v = [r.choice([0.5, 1, 2]) for _ in range(3)] if r.random() < 0.5 else [r.choice([0.5, 2])] * 3
            else:
                v = [self.grid(-1, 1) for _ in range(3)]
            self.add(depth, '<%s v="%s"/>' % (t, vec(v)))

    def shape(self):
        r = self.r
        kind = r.choice(["sphere", "sphere", "box", "box", "cylinder", "cone", "disc", "triangle", "mesh", "plane"])
        c = self.point(-2.5, 2.5, 0, 2)
        if kind == "sphere":
            head = '<sphere center="%s" radius="%s"' % (vec(c), fmt(r.choice([0.5, 1, 1.5])))
        elif kind == "box":
            d = [r.choice([0.5, 1, 2]) for _ in range(3)]
            head = '<box corner1="%s" corner2="%s"' % (vec(c), vec(x + y for x, y in zip(c, d)))
        elif kind == "cylinder":
            cap = (c[0], c[1] + r.choice([1, 2]), c[2]) if r.random() < 0.6 else (c[0] + 2, c[1], c[2])
            head = '<cylinder base="%s" cap="%s" radius="%s"%s' % (
                vec(c), vec(cap), fmt(r.choice([0.5, 1])), ' open="true"' if r.random() < 0.3 else "")
        elif kind == "cone":
            cap = (c[0], c[1] + r.choice([1, 2]), c[2])
            head = '<cone base="%s" base_radius="%s" cap="%s" cap_radius="%s"%s' % (
                vec(c), fmt(r.choice([0.5, 1])), vec(cap), fmt(r.choice([0, 0.25])),
                ' open="true"' if r.random() < 0.3 else "")
        elif kind == "disc":
            n = r.choice(["0 1 0", "0 0 1", "1 0 0", "0 1 1"])
            hole = ' hole_radius="0.5"' if r.random() < 0.3 else ""
            head = '<disc center="%s" normal="%s" radius="%s"%s' % (vec(c), n, fmt(r.choice([1, 1.5])), hole)
        elif kind == "triangle":
            p2 = (c[0] + r.choice([1, 2]), c[1], c[2])
            p3 = (c[0], c[1] + r.choice([1, 2]), c[2] + r.choice([0, 1]))
            head = '<triangle p1="%s" p2="%s" p3="%s"' % (vec(c), vec(p2), vec(p3))
        elif kind == "plane":
            n = r.choice(["1 0 0", "0 0 1", "-1 0 0", "0 0 -1", "1 0 1"])
            head = '<plane normal="%s" distance="%s"' % (n, fmt(r.choice([3, 4, 5])))
        else:  # a closed cube of twelve triangles
            self.add(1, "<mesh>")
            self.material(2)
            s = r.choice([1, 1.5])
            x, y, z = c
            v = [(x + dx * s, y + dy * s, z + dz * s) for dx in (0, 1) for dy in (0, 1) for dz in (0, 1)]
            faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                     (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
            for a, b, cc in faces:
                self.add(2, '<triangle p1="%s" p2="%s" p3="%s"/>' % (vec(v[a]), vec(v[b]), vec(v[cc])))
            self.transforms(2)
            self.add(1, "</mesh>")
            return
        if r.random() < 0.05:
            head += ' no_shadow="true"'
        self.add(1, head + ">")
        self.material(2)
        self.transforms(2)
        self.add(1, "</%s>" % kind)

    def make(self):
        r = self.r
        self.add(0, '<?xml version="1.0"?>')
        self.add(0, "<scene>")
        self.add(1, '<image width="160" height="100"/>')
        if r.random() < 0.3:
            self.add(1, '<global_settings max_trace_level="%d"/>' % r.choice([1, 3, 10]))
        self.add(1, '<background color="%s"/>' % vec(r.choice([(0, 0, 0), (0.2, 0.3, 0.5)])))
        self.camera()
        self.lights()
        if r.random() < 0.85:
            self.add(1, '<plane normal="0 1 0" distance="0">')
            self.add(2, "<pigment>")
            self.add(3, '<checker color1="0.9 0.9 0.9" color2="0.2 0.3 0.4"/>')
            self.add(2, "</pigment>")
            self.add(1, "</plane>")
        for _ in range(r.randint(2, 7)):
            self.shape()
        self.add(0, "</scene>")
        return "\n".join(self.lines) + "\n"


def run(cmd, **kw):
    return subprocess.run(cmd, text=True, capture_output=True, **kw)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=20, help="scenes (default 20)")
    ap.add_argument("--seed", type=int, default=1, help="the first scene's seed (default 1)")
    ap.add_argument("--out", default="/tmp/pvrt-difftest", help="folder (default /tmp/pvrt-difftest)")
    ap.add_argument("--pvrt", default=os.path.join(ROOT, "build", "pvrt"))
    ap.add_argument("--jobs", type=int, default=1, help="POV-Ray and pvrt renders at once (default 1)")
    ap.add_argument("--width", type=int, default=96, help="image width (default 96)")
    ap.add_argument("--variant", default="aa", help="reference variant name (default aa)")
    ap.add_argument("--render-option", action="append", default=[],
                    help="an option for pvrt's renders, e.g. --render-option=--pov-blocks (repeatable)")
    ap.add_argument("--antialiasing", default="+A0.0 +AM1 +R3 -J",
                    help="POV-Ray's antialiasing for the references (default '+A0.0 +AM1 +R3 -J'; "
                         "--antialiasing=-A for none)")
    a = ap.parse_args(argv)
    if not shutil.which("povray"):
        print("difftest: skipped: no povray on PATH (tools/install-deps.sh installs it)")
        return 77
    scenes = os.path.join(a.out, "scenes")
    os.makedirs(scenes, exist_ok=True)
    names = []
    for seed in range(a.seed, a.seed + a.count):
        name = "diff_%05d" % seed
        with open(os.path.join(scenes, name + ".xml"), "w") as f:
            f.write(SceneMaker(seed).make())
        names.append(name)
    make = [a.pvrt, "golden", "make", scenes] + names + ["--width", str(a.width), "--jobs", str(a.jobs)]
    if a.variant != "aa":
        make += ["--variant", a.variant]
    make += ["--antialiasing=" + a.antialiasing]  # one word: "-A" would read as an option
    got = run(make)
    if got.returncode != 0:
        sys.stderr.write(got.stdout + got.stderr)
        print("difftest: golden make failed (exit %d)" % got.returncode)
        return 2
    out = os.path.join(a.out, "run-" + a.variant)
    runcmd = [a.pvrt, "golden", "run", scenes, "--backends", "serial", "--jobs", str(a.jobs), "--out", out]
    if a.variant != "aa":
        runcmd += ["--variant", a.variant]
    runcmd += ["--render-option=" + o for o in a.render_option]
    got = run(runcmd)
    failed = []
    for line in got.stdout.splitlines():
        m = re.match(r"FAIL\s+(\S+)", line)
        if m and any(n in line for n in names):
            failed.append(line.strip())
    print("difftest: %d scenes (seeds %d-%d), variant %s: %d differ" % (
        a.count, a.seed, a.seed + a.count - 1, a.variant, len(failed)))
    for line in failed:
        print("  " + line)
    print("report: %s" % os.path.join(out, "report.html"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
