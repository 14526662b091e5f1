#!/usr/bin/env python3
"""The pointwise overlap of the surfaces of mortar zones against h and the choice of the slave
(doc/contact.md, "Non-matching meshes"):

    /usr/bin/python3 benchmarks/mortar_overlap.py [--exe build/feticontact]
        [--markdown doc/reports/data/mortar_overlap.md] [--levels 1,2,4] [--scenes two_blocks,punch,knife_edge]

Each scene with either surface as the slave, on its meshes and with every Subdivisions multiplied
by the levels (h / level). From summary.json: `mortar_overlap.slave_into_master` and
`mortar_overlap.master_into_slave` (the deepest vertex of one surface behind the other, relative
to max |u|), `kkt.penetration` (the rows' own check), and the rate log(o_{i−1}/o_i)/log(l_i/l_{i−1})
of the larger overlap against h. Scenes:
  - two_blocks: prm/two_blocks_nonmatching.prm (friction 0.5, the upper block pushed along x);
  - punch: tests/scenes/coarse_punch.prm (a coarse punch held down by 0.1 mm into a finer base);
  - knife_edge: the scene of benchmarks/knife_edge.py (a block half over the end of another).
Standard library only.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

from cli import arguments, option

TWO_BLOCKS_SWAP = ["Contact/Zone 2/Body=1", "Contact/Zone 2/Surface=z = zmax",
                   "Contact/Zone 2/Master body=2", "Contact/Zone 2/Master surface=z = zmin"]
SCENES = {
    "two_blocks": dict(
        prm="prm/two_blocks_nonmatching.prm", sets=[],
        meshes=[("Body 1", (16, 8, 4)), ("Body 2", (6, 6, 3))],
        slaves={"upper block's bottom (6 × 6)": [], "lower block's top (16 × 8)": TWO_BLOCKS_SWAP}),
    "punch": dict(
        prm="tests/scenes/coarse_punch.prm", sets=[],
        meshes=[("Body 1", (12, 12, 6)), ("Body 2", (3, 3, 2))],
        slaves={"punch's bottom (coarse)": [],
                "base's top (fine)": ["Contact/Zone 1/Body=1", "Contact/Zone 1/Surface=z = zmax",
                                      "Contact/Zone 1/Master body=2",
                                      "Contact/Zone 1/Master surface=z = zmin"]}),
    "knife_edge": dict(
        prm="prm/two_blocks_nonmatching.prm",
        sets=["Body 2/Mesh/Lower corner=1.5, 0, 0.5", "Body 2/Mesh/Upper corner=2.5, 1, 1",
              "Body 2/Boundary conditions/Tractions=z = zmax: 0, 0, -5e7"],
        meshes=[("Body 1", (16, 8, 4)), ("Body 2", (6, 6, 3))],
        slaves={"upper block's bottom": [], "lower block's top": TWO_BLOCKS_SWAP}),
}


def run(exe, prm, sets):
    with tempfile.TemporaryDirectory() as out:
        cmd = [exe, "--set", f"Output/Directory={out}", "--set", "Output/Write vtu=false"]
        for s in sets:
            cmd += ["--set", s]
        p = subprocess.run(cmd + [prm], capture_output=True, text=True,
                           env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        if p.returncode != 0:
            raise SystemExit(f"run failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr}")
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f), "Warning: the surfaces of a mortar zone" in p.stdout


def main():
    arguments(__doc__, ["--exe", "--markdown", "--levels", "--scenes"])
    exe = option("--exe", "build/feticontact")
    levels = [int(v) for v in option("--levels", "1,2,4").split(",")]
    scenes = option("--scenes", ",".join(SCENES)).split(",")
    out = ["<!-- written by benchmarks/mortar_overlap.py -->", "",
           f"Command: `python3 {' '.join(sys.argv)}`", "",
           "| scene | slave surface | h / level | contact nodes | slave into master "
           "| master into slave | rate | kkt.penetration | warning |",
           "|---|---|---|---|---|---|---|---|---|"]
    for name in scenes:
        scene = SCENES[name]
        for slave, slave_sets in scene["slaves"].items():
            previous = None
            for level in levels:
                mesh_sets = [f"{body}/Mesh/Subdivisions=" + ", ".join(str(level * n) for n in sub)
                             for body, sub in scene["meshes"]]
                s, warned = run(exe, scene["prm"], scene["sets"] + slave_sets + mesh_sets)
                o = s["mortar_overlap"]
                worst = max(o["slave_into_master"], o["master_into_slave"])
                rate = ("" if previous is None or worst <= 0 or previous[1] <= 0 else
                        f"{math.log(previous[1] / worst) / math.log(level / previous[0]):.2f}")
                previous = (level, worst)
                row = (f"| {name} | {slave} | {level} | {sum(s['contact'][k] for k in ('open', 'stick', 'slip'))} | "
                       f"{o['slave_into_master']:.2e} | {o['master_into_slave']:.2e} | {rate} | "
                       f"{s['kkt']['penetration']:.1e} | {'yes' if warned else 'no'} |")
                print(row, flush=True)
                out.append(row)
    path = option("--markdown", "doc/reports/data/mortar_overlap.md")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
