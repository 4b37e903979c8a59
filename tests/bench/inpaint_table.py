#!/usr/bin/env python3
"""The surface-inpainting comparison of BENCHMARKS.md ("Surface inpainting").

For each hole case of ../shared/data/meshes/cases and for the armadillo's right ear, writes the
variants' graphs by one rule, runs each with `geobrush run --json` and prints its distances to the
removed truth (geobrush.metrics' reference_* values):

  A  the fill (fill_holes)
  B  a plane template: cut_region -> primitive -> template_icp -> rbf_warp -> point_insert -> weld
  C  on the cases, B with one handle edit (a bulge at the hole's centre); on the ear, the other
     ear cut the same way and mirrored as the template, no edit
  D  the fill completed from examples (fragment_complete)
  E  on the ear only, a GeoBrush clone (graphs/methods/geobrush.json) of the other ear, mirrored,
     onto the fill of the cut

With --sweep instead: B on each case over template spacings of 0.5, 0.4 and 0.3 of the border's
and plane sizes of 2.8, 3.2 and 3.6 times the hole's radius, require_valid off, printing the new
self-intersections and the mean distance of each setting (--coarse: spacings of 1.0, 0.8 and 0.6,
templates as coarse as the border or coarser).

Usage: tests/bench/inpaint_table.py BUILD_DIR [OUT_DIR] [--sweep [--coarse]]
       (OUT_DIR: a new temp folder)
"""
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.path.normpath(os.path.join(HERE, '..', '..', '..', 'shared', 'data', 'meshes'))

# The ear to repair and the other ear (points at their middles), the x of the plane halfway
# between their tips, the geodesic radius painted to cut each, and the radius a clone copies (the
# ear and a rim of the head around it).
EAR = {'right': [0.090, 0.365, 0.175], 'left': [-0.120, 0.360, 0.150], 'mirror_x': -0.0157,
       'cut_radius': 0.075, 'clone_radius': 0.09}
METHODS = os.path.normpath(os.path.join(HERE, '..', '..', 'graphs', 'methods'))


def node(kind, **params):
    d = {"type": kind, "typeVersion": 1}
    if params:
        d["params"] = params
    return d


def graph(nodes, conns):
    return {"format": "geobrush-graph", "formatVersion": 1, "nodes": nodes,
            "connections": [{"from": a, "to": b} for a, b in conns]}


def read_obj(path):
    points, faces = [], []
    with open(path) as f:
        for line in f:
            s = line.split()
            if s and s[0] == 'v':
                points.append([float(x) for x in s[1:4]])
            elif s and s[0] == 'f':
                faces.append([int(x.split('/')[0]) - 1 for x in s[1:4]])
    return points, faces


def border_of(path):
    """The hole's border vertices (on edges with one face), the mesh's points and edges."""
    points, faces = read_obj(path)
    count = {}
    for f in faces:
        for i in range(3):
            e = tuple(sorted((f[i], f[(i + 1) % 3])))
            count[e] = count.get(e, 0) + 1
    border = {v for e, c in count.items() if c == 1 for v in e}
    return border, points, count


def plane_template(path, radius=None, width=3.2, spacing_factor=0.5):
    """A plane `width` times the hole's radius wide (by default the border's mean distance to its
    centroid), its vertices at most `spacing_factor` times the border's spacing apart (the median
    edge length at the border's vertices)."""
    border, points, edges = border_of(path)
    if radius is None:
        centre = [sum(points[v][i] for v in border) / len(border) for i in range(3)]
        radius = sum(math.dist(points[v], centre) for v in border) / len(border)
    lengths = sorted(math.dist(points[a], points[b]) for (a, b) in edges
                     if a in border or b in border)
    n = len(lengths)
    spacing = lengths[n // 2] if n % 2 else (lengths[n // 2 - 1] + lengths[n // 2]) / 2
    size = round(width * radius, 4)
    return size, math.ceil(size / (spacing_factor * spacing)), radius


def border_normal(path):
    """The mean normal of the faces at the hole's border: the surface's outward direction."""
    border, points, _ = border_of(path)
    _, faces = read_obj(path)
    n = [0.0, 0.0, 0.0]
    for f in faces:
        if any(v in border for v in f):
            a, b, c = (points[v] for v in f)
            u = [b[i] - a[i] for i in range(3)]
            w = [c[i] - a[i] for i in range(3)]
            cross = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            n = [n[i] + cross[i] for i in range(3)]
    length = math.sqrt(sum(x * x for x in n))
    return [x / length for x in n]


def template_chain(nodes, conns, template):
    nodes["icp"] = node("geobrush.template_icp")
    nodes["warp"] = node("geobrush.rbf_warp", distance="straight", t_max_auto="border_radius",
                         reg=0.01)
    nodes["insert"] = node("geobrush.point_insert")
    nodes["weld"] = node("geobrush.weld")
    conns += [(template, "icp.template"), ("hole.border", "icp.border"),
              ("icp.template", "warp.template"), ("icp.pairs", "warp.pairs"),
              ("warp.template", "insert.template"), ("hole.border", "insert.border"),
              ("hole.border", "weld.border"), ("insert.template", "weld.patch")]


def fill_chain(nodes, conns, holed, complete, stride):
    nodes["fill"] = node("geobrush.fill_holes")
    conns.append((holed, "fill.mesh"))
    if not complete:
        return "fill.mesh"
    nodes["complete"] = node("geobrush.fragment_complete", candidate_stride=stride)
    conns += [("fill.mesh", "complete.mesh"), ("fill.map", "complete.paste_map")]
    return "complete.mesh"


def measured(nodes, conns, holed, truth, result, mapping):
    nodes["metrics"] = node("geobrush.metrics", require_valid=True)
    nodes["save_result"] = node("geobrush.save_mesh", path="result.obj")
    conns += [(result, "metrics.mesh"), (mapping, "metrics.map"), (holed, "metrics.target"),
              (truth, "metrics.reference"), (result, "save_result.mesh")]
    return graph(nodes, conns)


def case_graphs(case, width=3.2, spacing_factor=0.5):
    """A-D on a hole case: the hole is the mesh's loop nearest the case's centre point."""
    hole_path = f"{MESHES}/cases/{case}_hole.obj"
    with open(f"{MESHES}/cases/{case}_hole.json") as f:
        description = json.load(f)
    near = description["center_point"]
    size, resolution, radius = plane_template(hole_path, description["radius"], width,
                                              spacing_factor)
    stride = max(1, math.ceil(len(read_obj(hole_path)[0]) / 5000))

    def start():
        return ({"hole_mesh": node("geobrush.load_mesh", path=hole_path),
                 "truth": node("geobrush.load_mesh",
                               path=f"{MESHES}/cases/{case}_removed_patch.obj"),
                 "hole": node("geobrush.cut_region", near=near)},
                [("hole_mesh.mesh", "hole.mesh")])

    def templated(edit):
        nodes, conns = start()
        nodes["template"] = node("geobrush.primitive", shape="plane", size=size,
                                 resolution=resolution)
        template_chain(nodes, conns, "template.mesh")
        shaped = "warp.template"
        if edit:
            # The template's point nearest the centre, a handle a tenth of the radius, raised by
            # 0.15 radius along the surface's normal.
            lift = [0.15 * radius * x for x in border_normal(hole_path)]
            nodes["edit"] = node("geobrush.handle_edit",
                                 edits=[near + [0.1 * radius] + lift + [0, 0, 1, 0]])
            conns += [("warp.template", "edit.template"), ("edit.template", "insert.template")]
            conns.remove(("warp.template", "insert.template"))
        return measured(nodes, conns, "hole_mesh.mesh", "truth.mesh", "weld.mesh",
                        "weld.paste_map")

    def filled(complete):
        nodes, conns = start()
        result = fill_chain(nodes, conns, "hole_mesh.mesh", complete, stride)
        return measured(nodes, conns, "hole_mesh.mesh", "truth.mesh", result, "fill.map")

    return {"A fill": filled(False), "B plane": templated(False),
            "C plane + edit": templated(True), "D fill + completion": filled(True)}


def cut(nodes, conns, name, centre):
    """cut_region removing what a dab of the cut radius paints on a geodesic canvas there."""
    r = EAR["cut_radius"]
    nodes[f"{name}_canvas"] = node("geobrush.canvas_grow", origin=centre, dabs=[centre + [1.6 * r]])
    nodes[f"{name}_map"] = node("geobrush.gdem")
    nodes[f"{name}_strokes"] = node("geobrush.strokes", dabs=[[0, 0, r, 1]])
    nodes[name] = node("geobrush.cut_region")
    conns += [("mesh.mesh", f"{name}_canvas.mesh"),
              (f"{name}_canvas.canvas", f"{name}_map.canvas"), ("mesh.mesh", f"{name}.mesh"),
              (f"{name}_map.parameterization", f"{name}.canvas"),
              (f"{name}_strokes.strokes", f"{name}.strokes")]


def ear_start():
    nodes = {"mesh": node("geobrush.load_mesh", path=f"{MESHES}/armadillo.obj")}
    conns = []
    cut(nodes, conns, "hole", EAR["right"])
    return nodes, conns


def ear_graphs(build, out):
    """A-D on the armadillo's right ear; the plane is sized on the cut, run once first."""
    nodes, conns = ear_start()
    nodes["save_holed"] = node("geobrush.save_mesh", path="holed.obj")
    conns.append(("hole.mesh", "save_holed.mesh"))
    fill_chain(nodes, conns, "hole.mesh", False, 1)
    nodes["save_fill"] = node("geobrush.save_mesh", path="filled.obj")
    conns.append(("fill.mesh", "save_fill.mesh"))
    run(build, graph(nodes, conns), os.path.join(out, "ear_cut"))
    size, resolution, _ = plane_template(os.path.join(out, "ear_cut", "holed.obj"))
    clone_target = fill_centre(os.path.join(out, "ear_cut"))

    def filled(complete):
        nodes, conns = ear_start()
        result = fill_chain(nodes, conns, "hole.mesh", complete, 3)
        return measured(nodes, conns, "hole.mesh", "hole.removed", result, "fill.map")

    nodes, conns = ear_start()
    nodes["template"] = node("geobrush.primitive", shape="plane", size=size, resolution=resolution)
    template_chain(nodes, conns, "template.mesh")
    plane = measured(nodes, conns, "hole.mesh", "hole.removed", "weld.mesh", "weld.paste_map")

    nodes, conns = ear_start()
    cut(nodes, conns, "other", EAR["left"])
    nodes["mirror"] = node("geobrush.transform", scale=[-1.0, 1.0, 1.0],
                           pivot=[EAR["mirror_x"], 0.0, 0.0])
    conns.append(("other.removed", "mirror.mesh"))
    template_chain(nodes, conns, "mirror.mesh")
    other = measured(nodes, conns, "hole.mesh", "hole.removed", "weld.mesh", "weld.paste_map")
    return {"A fill": filled(False), "B plane": plane, "C the other ear": other,
            "D fill + completion": filled(True), "E GeoBrush clone of the other ear": cloned(clone_target)}


def fill_centre(folder):
    """The fill's vertex nearest the centroid of the cut's border: where the ear stood."""
    border, points, _ = border_of(os.path.join(folder, "holed.obj"))
    hole = [v for v in border if math.dist(points[v], EAR["right"]) < 3 * EAR["cut_radius"]]
    centroid = [sum(points[v][k] for v in hole) / len(hole) for k in range(3)]
    filled, _ = read_obj(os.path.join(folder, "filled.obj"))
    return min(filled, key=lambda p: math.dist(p, centroid))


def cloned(target):
    """GeoBrush's clone method from the mirrored armadillo's left ear onto the fill of the cut at
    `target`, set as `geobrush clone` sets its template (radius, points; scale 1, no turn)."""
    with open(os.path.join(METHODS, "geobrush.json")) as f:
        method = json.load(f)
    nodes, conns = ear_start()
    fill_chain(nodes, conns, "hole.mesh", False, 1)
    nodes["mirror"] = node("geobrush.transform", scale=[-1.0, 1.0, 1.0],
                           pivot=[EAR["mirror_x"], 0.0, 0.0])
    conns.append(("mesh.mesh", "mirror.mesh"))
    rename = {"source_mesh.mesh": "mirror.mesh", "target_mesh.mesh": "fill.mesh"}
    for name, n in method["nodes"].items():
        if name not in ("source_mesh", "target_mesh", "save_result", "render_result", "metrics"):
            nodes[name] = n
    conns += [(rename.get(c["from"], c["from"]), c["to"]) for c in method["connections"]
              if not c["to"].split(".")[0] in ("save_result", "render_result", "metrics")]
    left = EAR["left"]
    source = [2 * EAR["mirror_x"] - left[0], left[1], left[2]]
    r = EAR["clone_radius"]
    nodes["source_canvas"]["params"] = {"origin": source, "dabs": source + [2 * r]}
    nodes["strokes"]["params"] = {"dabs": [0, 0, r, 1]}
    nodes["target_map"]["params"] = {"origin": target}
    return measured(nodes, conns, "fill.mesh", "hole.removed", "stitch.mesh", "stitch.map")


def run(build, g, folder):
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "graph.json")
    with open(path, "w") as f:
        json.dump(g, f, indent=2)
    done = subprocess.run([os.path.join(build, "bin", "geobrush"), "run", "--json", path],
                          capture_output=True, text=True)
    if done.returncode != 0:
        return None, done.stderr.strip().splitlines()[-1:] or ["failed"]
    return json.loads(done.stdout)["metrics"], None


def row(label, metrics, error):
    if error:
        return f"| {label} | refused: {error[0]} |"
    m = lambda k: metrics["metrics." + k]
    return (f"| {label} | {m('reference_mean_distance'):.2e} / {m('reference_max_distance'):.1e} / "
            f"{m('reference_normal_mean_deg'):.1f} deg | {m('reference_to_result_mean_distance'):.2e}"
            f" / {m('reference_to_result_max_distance'):.1e} |")


def sweep(build, out, cases, spacings):
    valid = 0
    for case in cases:
        for spacing_factor in spacings:
            for width in (2.8, 3.2, 3.6):
                g = case_graphs(case, width, spacing_factor)["B plane"]
                g["nodes"]["metrics"]["params"]["require_valid"] = False
                folder = os.path.join(out, "sweep", f"{case}-{spacing_factor}-{width}")
                metrics, error = run(build, g, folder)
                if error:
                    print(f"{case} spacing {spacing_factor} width {width}: failed: {error[0]}")
                    continue
                crossings = metrics["metrics.new_self_intersections"]
                valid += crossings == 0 and metrics["metrics.manifold"] == 1
                print(f"{case} spacing {spacing_factor} width {width}: {crossings:.0f} new "
                      f"self-intersections, mean distance "
                      f"{metrics['metrics.reference_mean_distance']:.2e}", flush=True)
    print(f"valid in {valid} of {9 * len(cases)} settings")


def main():
    arguments = [a for a in sys.argv[1:] if a not in ("--sweep", "--coarse")]
    if not arguments:
        sys.exit(__doc__)
    build = os.path.abspath(arguments[0])
    out = arguments[1] if len(arguments) > 1 else tempfile.mkdtemp(prefix="inpaint-table-")
    cases = sorted(f[:-len("_hole.obj")] for f in os.listdir(f"{MESHES}/cases")
                   if f.endswith("_hole.obj"))
    if "--sweep" in sys.argv:
        sweep(build, out, cases, (1.0, 0.8, 0.6) if "--coarse" in sys.argv else (0.5, 0.4, 0.3))
        return
    print("| case, variant | new vertices to the truth: mean / max / normals | "
          "the truth to the result: mean / max |")
    print("|---|---|---|")
    for case in cases:
        for variant, g in case_graphs(case).items():
            print(row(f"{case}, {variant}", *run(build, g, os.path.join(out, case, variant[0]))),
                  flush=True)
    for variant, g in ear_graphs(build, out).items():
        print(row(f"armadillo ear, {variant}", *run(build, g, os.path.join(out, "ear", variant[0]))),
              flush=True)
    print(f"(graphs and results in {out})")


if __name__ == "__main__":
    main()
