#!/usr/bin/env python3
"""Convert the third-party NURBS models into nurbs-scene/1 files, once.

    scripts/convert_models.py            write scenes/data/teapot.json and scenes/data/duck.json
    scripts/convert_models.py --check    verify those files (no writing), exit 1 on any mismatch

Sources (see shared/data/models/README.md):
  teapot.bpt          mkeeter/teapot-mrep : teapot.bpt  (Newell's Utah teapot, public data set)
  duck{1,2,3}.nurbs   glscene/GLScene : Assets/Model/duck{1,2,3}.nurbs  (MPL-2.0)

The check does not trust this converter: it reads the written JSON back and compares it with the
OpenCASCADE dumps in shared/data/reference-values/{teapot,duck}_occt.json (degrees, knots, control
points, weights, all exact), then evaluates every surface at each OCCT (u, v) with the small
rational de Boor evaluator below and compares with OCCT's point (1e-9 relative to the surface's
largest absolute coordinate). It also re-converts the sources and requires the files on disk to be
byte-identical (deterministic, not stale).

Python 3 standard library only.
"""

import argparse
import json
import math
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT_DIR = os.path.join(ROOT, "scenes", "data")


def default_shared():
    # The shared data folder, if present: <checkout>/shared, or shared/ beside the checkout.
    for cand in (os.path.join(ROOT, "shared"), os.path.join(os.path.dirname(ROOT), "shared")):
        if os.path.isdir(os.path.join(cand, "data", "models")):
            return cand
    return os.path.join(os.path.dirname(ROOT), "shared")


TEAPOT_DESCRIPTION = (
    "Newell's Utah teapot: 32 bicubic Bezier patches (8 of them with a collapsed edge, so normals "
    "are degenerate there). Source: mkeeter/teapot-mrep : teapot.bpt (the same data as freeglut's "
    "fg_teapot_data.h); licence: public data set. Converted by scripts/convert_models.py: each "
    "patch became a non-rational B-spline with knots [0,0,0,0,1,1,1,1]; point k of a patch has "
    "u-index k/(dv+1) and v-index k%(dv+1); patches teapot_00..teapot_31 in file order.")

DUCK_DESCRIPTION = (
    "The classic three-surface NURBS duck (duck1 body, duck2 and duck3 the head pieces), bicubic "
    "with non-uniform knots; duck1 is rational (weights 0.5 to 1), closes on itself along u (seam "
    "at u = -pi/pi) and has two collapsed poles (v = -pi/2 and v = pi/2). Source: glscene/GLScene : "
    "Assets/Model/duck1.nurbs, duck2.nurbs, duck3.nurbs; licence: MPL-2.0. Converted by "
    "scripts/convert_models.py from the VRML97 NurbsSurface fields (order = degree + 1, control "
    "point index i + j*uDimension with u fastest); knot values kept exactly as written (duck1's "
    "6.66134e-016 is the file's value, not zero).")


# ----------------------------------------------------------------------------- readers

def read_teapot(path):
    tokens = open(path, encoding="ascii").read().split()
    pos = 0

    def take():
        nonlocal pos
        if pos >= len(tokens):
            raise ValueError(f"{path}: unexpected end of file")
        pos += 1
        return tokens[pos - 1]

    count = int(take())
    surfaces = []
    for patch in range(count):
        du, dv = int(take()), int(take())
        n = (du + 1) * (dv + 1)
        pts = [[float(take()), float(take()), float(take())] for _ in range(n)]
        # Point k: u-index k // (dv+1), v-index k % (dv+1) -> already u-major; our index i*count_v+j
        # equals k, so the order is kept as is.
        surfaces.append({
            "name": f"teapot_{patch:02d}",
            "degree_u": du, "degree_v": dv,
            "count_u": du + 1, "count_v": dv + 1,
            "knots_u": [0.0] * (du + 1) + [1.0] * (du + 1),
            "knots_v": [0.0] * (dv + 1) + [1.0] * (dv + 1),
            "points": pts,
            "weights": None,
        })
    if pos != len(tokens):
        raise ValueError(f"{path}: {len(tokens) - pos} trailing tokens")
    return surfaces


VRML_IGNORED = {"ccw", "solid"}  # shading/culling only, no effect on the geometry


def read_vrml_nurbs(path, name):
    text = open(path, encoding="ascii").read()
    text = re.sub(r"#[^\n]*", " ", text)
    tokens = re.findall(r"\[|\]|[^\s,\[\]]+", text)
    fields = {}
    pos = 0
    while pos < len(tokens):
        key = tokens[pos]
        pos += 1
        if pos < len(tokens) and tokens[pos] == "[":
            end = tokens.index("]", pos)
            fields[key] = tokens[pos + 1:end]
            pos = end + 1
        else:
            fields[key] = tokens[pos]
            pos += 1
    known = {"uOrder", "vOrder", "uDimension", "vDimension", "uKnot", "vKnot", "controlPoint",
             "weight"} | VRML_IGNORED
    unknown = set(fields) - known
    if unknown:
        raise ValueError(f"{path}: unknown fields {sorted(unknown)}")
    nu, nv = int(fields["uDimension"]), int(fields["vDimension"])
    pu, pv = int(fields["uOrder"]) - 1, int(fields["vOrder"]) - 1
    knots_u = [float(t) for t in fields["uKnot"]]
    knots_v = [float(t) for t in fields["vKnot"]]
    flat = [float(t) for t in fields["controlPoint"]]
    if len(flat) != 3 * nu * nv:
        raise ValueError(f"{path}: {len(flat)} coordinates, need 3*{nu}*{nv}")
    if len(knots_u) != nu + pu + 1 or len(knots_v) != nv + pv + 1:
        raise ValueError(f"{path}: knot counts {len(knots_u)}, {len(knots_v)} do not match")
    w_flat = [float(t) for t in fields["weight"]] if "weight" in fields else [1.0] * (nu * nv)
    if len(w_flat) != nu * nv:
        raise ValueError(f"{path}: {len(w_flat)} weights, need {nu * nv}")
    # VRML index = i + j*nu (u fastest)  ->  ours = i*nv + j (v fastest).
    points, weights = [], []
    for i in range(nu):
        for j in range(nv):
            k = i + j * nu
            points.append(flat[3 * k:3 * k + 3])
            weights.append(w_flat[k])
    return {
        "name": name,
        "degree_u": pu, "degree_v": pv,
        "count_u": nu, "count_v": nv,
        "knots_u": knots_u, "knots_v": knots_v,
        "points": points,
        "weights": None if all(w == 1.0 for w in weights) else weights,
    }


# ----------------------------------------------------------------------------- writer

def num(x):
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"non-finite number {x!r}")
    return repr(x)


def scene_text(name, description, surfaces):
    out = ["{",
           '  "format": "nurbs-scene/1",',
           f'  "name": {json.dumps(name)},',
           f'  "description": {json.dumps(description)},',
           '  "surfaces": [']
    for s_index, s in enumerate(surfaces):
        out.append("    {")
        out.append(f'      "name": {json.dumps(s["name"])},')
        for key in ("degree_u", "degree_v", "count_u", "count_v"):
            out.append(f'      "{key}": {int(s[key])},')
        for key in ("knots_u", "knots_v"):
            out.append(f'      "{key}": [' + ", ".join(num(k) for k in s[key]) + "],")
        out.append('      "points": [')
        pts = s["points"]
        for k, p in enumerate(pts):
            out.append("        [" + ", ".join(num(c) for c in p) + "]" +
                       ("," if k + 1 < len(pts) else ""))
        if s["weights"] is None:
            out.append("      ]")
        else:
            out.append("      ],")
            out.append('      "weights": [')
            nv = s["count_v"]
            rows = [s["weights"][i * nv:(i + 1) * nv] for i in range(s["count_u"])]
            for i, row in enumerate(rows):  # one line per u-index
                out.append("        " + ", ".join(num(w) for w in row) +
                           ("," if i + 1 < len(rows) else ""))
            out.append("      ]")
        out.append("    }" + ("," if s_index + 1 < len(surfaces) else ""))
    out.append("  ]")
    out.append("}")
    return "\n".join(out) + "\n"


def build(shared):
    models = os.path.join(shared, "data", "models")
    teapot = read_teapot(os.path.join(models, "teapot.bpt"))
    ducks = [read_vrml_nurbs(os.path.join(models, f"duck{n}.nurbs"), f"duck{n}") for n in (1, 2, 3)]
    return {
        "teapot.json": scene_text("teapot", TEAPOT_DESCRIPTION, teapot),
        "duck.json": scene_text("duck", DUCK_DESCRIPTION, ducks),
    }


# ----------------------------------------------------------------------------- evaluator

def find_span(knots, p, n, x):
    """Index k with knots[k] <= x < knots[k+1], p <= k <= n-1, knots[k] < knots[k+1]; the last
    non-empty span at the right end of the domain, the first one left of it."""
    if x >= knots[n]:
        k = n - 1
        while knots[k] >= knots[k + 1]:
            k -= 1
        return k
    k = p
    while k < n - 1 and knots[k + 1] <= x:
        k += 1
    return k


def de_boor(knots, p, k, x, ctrl):
    """de Boor's algorithm on homogeneous points ctrl[k-p..k] (list of 4-lists)."""
    d = [list(ctrl[j + k - p]) for j in range(p + 1)]
    for r in range(1, p + 1):
        for j in range(p, r - 1, -1):
            lo, hi = knots[j + k - p], knots[j + 1 + k - r]
            a = (x - lo) / (hi - lo)
            d[j] = [(1.0 - a) * d[j - 1][c] + a * d[j][c] for c in range(4)]
    return d[p]


def evaluate(s, u, v):
    pu, pv, nu, nv = s["degree_u"], s["degree_v"], s["count_u"], s["count_v"]
    pts = s["points"]
    wts = s.get("weights") or [1.0] * (nu * nv)
    ku = find_span(s["knots_u"], pu, nu, u)
    kv = find_span(s["knots_v"], pv, nv, v)
    rows = {}
    for i in range(ku - pu, ku + 1):
        hom = []
        for j in range(nv):
            w = wts[i * nv + j]
            x, y, z = pts[i * nv + j]
            hom.append([w * x, w * y, w * z, w])
        rows[i] = de_boor(s["knots_v"], pv, kv, v, hom)
    col = [rows.get(i, [0.0] * 4) for i in range(nu)]
    h = de_boor(s["knots_u"], pu, ku, u, col)
    return [h[0] / h[3], h[1] / h[3], h[2] / h[3]]


# ----------------------------------------------------------------------------- check

def traps(s):
    """Human-readable notes on collapsed edges, seams, odd knots."""
    notes = []
    nu, nv = s["count_u"], s["count_v"]
    P = lambda i, j: s["points"][i * nv + j]
    edges = {
        "u=min (i=0)": [P(0, j) for j in range(nv)],
        "u=max (i=last)": [P(nu - 1, j) for j in range(nv)],
        "v=min (j=0)": [P(i, 0) for i in range(nu)],
        "v=max (j=last)": [P(i, nv - 1) for i in range(nu)],
    }
    for label, e in edges.items():
        if all(q == e[0] for q in e):
            notes.append(f"collapsed edge {label} -> pole {e[0]}")
    if edges["u=min (i=0)"] == edges["u=max (i=last)"]:
        notes.append("closed in u (seam: i=0 row == i=last row)")
    if edges["v=min (j=0)"] == edges["v=max (j=last)"]:
        notes.append("closed in v (seam: j=0 column == j=last column)")
    for key in ("knots_u", "knots_v"):
        for x in s[key]:
            if x != 0.0 and abs(x) < 1e-12:
                notes.append(f"{key} contains {x!r} (round-off for 0 in the exporter, kept)")
    if s.get("weights"):
        notes.append(f"rational, weights {min(s['weights'])}..{max(s['weights'])}")
    return notes


def check(shared):
    ok = True
    fresh = build(shared)
    ref_dir = os.path.join(shared, "data", "reference-values")
    overall = 0.0
    for fname, ref_name in (("teapot.json", "teapot_occt.json"), ("duck.json", "duck_occt.json")):
        path = os.path.join(OUT_DIR, fname)
        text = open(path, encoding="utf-8").read()
        if text != fresh[fname]:
            print(f"FAIL {fname}: differs from a fresh conversion (stale or non-deterministic)")
            ok = False
        scene = json.loads(text)
        ref = json.load(open(os.path.join(ref_dir, ref_name), encoding="utf-8"))
        if scene.get("format") != "nurbs-scene/1":
            print(f"FAIL {fname}: format {scene.get('format')!r}")
            ok = False
        names = [s["name"] for s in scene["surfaces"]]
        if names != list(ref["surfaces"].keys()):
            print(f"FAIL {fname}: surface names {names} != OCCT {list(ref['surfaces'])}")
            ok = False
        file_max_rel = 0.0
        file_evals = 0
        print(f"{fname}: {len(names)} surfaces vs {ref_name} ({ref['computed_with']})")
        for s in scene["surfaces"]:
            r = ref["surfaces"].get(s["name"])
            if r is None:
                print(f"  FAIL {s['name']}: not in {ref_name}")
                ok = False
                continue
            problems = []
            nu, nv = s["count_u"], s["count_v"]
            if len(s["points"]) != nu * nv:
                problems.append("point count")
            for key in ("degree_u", "degree_v"):
                if s[key] != r[key]:
                    problems.append(f"{key} {s[key]} != {r[key]}")
            for key in ("knots_u", "knots_v"):
                if s[key] != r[key]:
                    problems.append(f"{key} differs: {s[key]} vs {r[key]}")
            cu = r["ctrl_u_major"]
            if len(cu) != nu or any(len(row) != nv for row in cu):
                problems.append(f"OCCT net is {len(cu)}x{len(cu[0])}, ours {nu}x{nv} "
                                "(u/v swapped?)")
            else:
                wts = s.get("weights") or [1.0] * (nu * nv)
                bad_p = [(i, j) for i in range(nu) for j in range(nv)
                         if cu[i][j] != s["points"][i * nv + j]]
                bad_w = [(i, j) for i in range(nu) for j in range(nv)
                         if r["weights_u_major"][i][j] != wts[i * nv + j]]
                if bad_p:
                    problems.append(f"{len(bad_p)} control points differ, first at (i,j)={bad_p[0]}")
                if bad_w:
                    problems.append(f"{len(bad_w)} weights differ, first at (i,j)={bad_w[0]}")
            scale = max(abs(c) for p in s["points"] for c in p)
            max_abs = 0.0
            worst = None
            for e in r["evals"]:
                u, v, ref_p = e[0], e[1], e[2:5]
                p = evaluate(s, u, v)
                d = max(abs(p[c] - ref_p[c]) for c in range(3))
                if d >= max_abs:
                    max_abs, worst = d, (u, v)
            rel = max_abs / scale
            file_max_rel = max(file_max_rel, rel)
            file_evals += len(r["evals"])
            if rel > 1e-9:
                problems.append(f"point deviation {rel:.3e} relative > 1e-9 at (u,v)={worst}")
            status = "FAIL" if problems else "ok  "
            ok = ok and not problems
            notes = traps(s)
            print(f"  {status} {s['name']}: {nu}x{nv} deg {s['degree_u']},{s['degree_v']}  "
                  f"{len(r['evals'])} evals, max |dP| {max_abs:.3e} abs, {rel:.3e} rel "
                  f"(scale {scale})" + ("; " + "; ".join(notes) if notes else ""))
            for pr in problems:
                print(f"       {pr}")
        print(f"  {fname}: {file_evals} evals, max deviation {file_max_rel:.3e} relative")
        overall = max(overall, file_max_rel)
    print(f"overall max point deviation: {overall:.3e} relative (tolerance 1e-9) -> "
          f"{'PASS' if ok else 'FAIL'}")
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="verify the written files, write nothing")
    ap.add_argument("--shared", default=default_shared(), help="the shared/ folder (data/models)")
    args = ap.parse_args()
    if args.check:
        return 0 if check(args.shared) else 1
    os.makedirs(OUT_DIR, exist_ok=True)
    for fname, text in build(args.shared).items():
        path = os.path.join(OUT_DIR, fname)
        with open(path, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        print(f"wrote {os.path.relpath(path, ROOT)} ({len(text.encode())} bytes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
