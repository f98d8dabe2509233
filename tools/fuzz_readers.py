"""Mutation fuzzing of every reader: random byte edits of valid files, each read through the
public loaders; anything but the reader's InputError (or a clean result) is counted and shown.

    python tools/fuzz_readers.py [--n 300] [--seed 0]

Run it in a subprocess per reader so that a crash (a segfault in a C extension) is counted
too. Prints a table: reader, inputs, loaded, refused cleanly, other exceptions, crashes.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

WORKER = r'''
import random, sys, traceback, shutil, os
from pathlib import Path
import patternfit as pf
from patternfit.errors import InputError
from patternfit.mesh.store import load_garment
from patternfit.loop.session import DesignSession
kind, src, n, seed, tmp = sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), Path(sys.argv[5])
rng = random.Random(seed)
def mutate(data: bytes) -> bytes:
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        op = rng.random()
        if not b: break
        i = rng.randrange(len(b))
        if op < 0.3: b[i] = rng.randrange(256)
        elif op < 0.5: del b[i:i + rng.randint(1, 50)]
        elif op < 0.7: b[i:i] = rng.choice([b"[", b"]", b"{", b"-", b"1e308", b"NaN", b'"', b",", b"0" * 30, b"\xff"])
        elif op < 0.85: b = b[:i]
        else: b[i:i] = b[max(0, i - 40):i]
    return bytes(b)
load = {"pattern": pf.read_pattern, "garmentcode": pf.read_pattern, "dxf": pf.read_pattern,
        "body": pf.read_body, "fabric": pf.read_fabric, "garment": load_garment,
        "session": DesignSession.load}[kind]
ok = refused = other = 0
shown = []
for k in range(n):
    if src.is_dir():
        d = tmp / f"case{k}"
        shutil.copytree(src, d)
        files = [p for p in d.rglob("*") if p.is_file()]
        f = rng.choice(files)
        f.write_bytes(mutate(f.read_bytes()))
        target = d
    else:
        target = tmp / f"case{k}{src.suffix}"
        target.write_bytes(mutate(src.read_bytes()))
        side = src.with_suffix(".seams.json")
        if side.exists():
            t2 = target.with_suffix(".seams.json")
            t2.write_bytes(mutate(side.read_bytes()) if rng.random() < 0.5 else side.read_bytes())
    try:
        load(target if kind != "fabric" else str(target))
        ok += 1
    except InputError as exc:
        refused += 1
        if not str(exc).startswith(str(tmp)):
            other += 1; shown.append(f"unnamed file: {exc}"[:160])
    except Exception as exc:
        other += 1
        shown.append(f"{type(exc).__name__}: {exc}"[:160])
print(ok, refused, other)
for s in shown[:5]: print("  ", s)
'''


def _sources(tmp: Path) -> dict:
    """One valid file (or folder) per reader, written by the package's own writers and by
    hand the way other tools write them."""
    import patternfit as pf
    from patternfit.body import load_body, save_body_mesh
    from patternfit.loop.session import DesignSession
    from patternfit.pattern.formats import save_any_pattern

    skirt = pf.read_pattern("skirt")
    out = {}
    save_any_pattern(skirt, tmp / "skirt.json")
    out["pattern"] = tmp / "skirt.json"
    save_any_pattern(skirt, tmp / "skirt_specification.json", fmt="garmentcode")
    out["garmentcode"] = tmp / "skirt_specification.json"
    save_any_pattern(skirt, tmp / "skirt.dxf")
    out["dxf"] = tmp / "skirt.dxf"
    body = load_body("female_thin")
    save_body_mesh(body, tmp / "body.obj")
    out["body"] = tmp / "body.obj"
    (tmp / "fabric.json").write_text(json.dumps({
        "name": "poplin", "density": 0.115, "stretch_warp": 6000, "stretch_weft": 4000,
        "shear": 40, "bending": 6e-6, "friction": 0.4, "thickness": 0.00025}))
    out["fabric"] = tmp / "fabric.json"
    m = pf.mesh_garment(skirt, triangles=300)
    pf.save_garment(tmp / "garment", skirt, m)
    out["garment"] = tmp / "garment"
    s = DesignSession(skirt, body, "denim", triangles=300)
    s.save(tmp / "session")
    out["session"] = tmp / "session"
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=300, help="mutated inputs per reader")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--only", default="", help="comma-separated readers")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        sources = _sources(tmp)
        print(f"{'reader':12} {'inputs':>6} {'loaded':>6} {'refused':>7} {'other':>5} crashed")
        for kind, src in sources.items():
            if args.only and kind not in args.only.split(","):
                continue
            work = tmp / f"work-{kind}"
            work.mkdir()
            r = subprocess.run([sys.executable, "-c", WORKER, kind, str(src), str(args.n),
                                str(args.seed), str(work)], capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{kind:12} {args.n:6} {'':>6} {'':>7} {'':>5} yes (rc {r.returncode}): "
                      f"{r.stderr.strip().splitlines()[-1:]}")
                continue
            lines = r.stdout.strip().splitlines()
            ok, refused, other = map(int, lines[0].split())
            print(f"{kind:12} {args.n:6} {ok:6} {refused:7} {other:5} no")
            for line in lines[1:]:
                print(line)


if __name__ == "__main__":
    main()
