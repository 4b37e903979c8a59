"""geobrush.Graph and geobrush.Evaluator: graphs built and edited in Python, evaluated with the
command's evaluator and cache."""

import json

import numpy as np
import pytest

import geobrush


def sphere_graph(out_name="sphere.obj"):
    """primitive (sphere) -> transform -> save."""
    graph = geobrush.Graph()
    graph.add_node("shape", "geobrush.primitive", shape="sphere", size=2.0, resolution=8)
    graph.add_node("move", "geobrush.transform", translate=(1, 2, 3))
    graph.add_node("save", "geobrush.save_mesh", path=out_name)
    graph.connect("shape.mesh", "move.mesh")
    graph.connect("move.mesh", "save.mesh")
    return graph


def test_a_built_graph_evaluates_to_the_analytic_shape(tmp_path):
    graph = sphere_graph()
    report = geobrush.Evaluator().evaluate(graph, out_dir=tmp_path)
    assert report.ok and report.computed == 3 and report.cache_hits == 0
    assert [str(p) for p in report.files_written] == [str(tmp_path / "sphere.obj")]
    assert set(report.node_times) == {"shape", "move", "save"}
    mesh = geobrush.read_mesh(tmp_path / "sphere.obj")
    # A sphere of radius 2 around (1, 2, 3): every vertex on it.
    distances = np.linalg.norm(mesh.vertices - [1, 2, 3], axis=1)
    np.testing.assert_allclose(distances, 2, rtol=1e-12)


def test_outputs_come_as_python_values(tmp_path):
    graph = sphere_graph()
    graph.add_node("picture", "geobrush.render", path="", width=64, height=48)
    graph.connect("move.mesh", "picture.mesh")
    evaluator = geobrush.Evaluator()
    evaluator.evaluate(graph, out_dir=tmp_path)
    mesh = evaluator.output("move", "mesh")
    assert isinstance(mesh, geobrush.Mesh)
    saved = geobrush.read_mesh(tmp_path / "sphere.obj")
    np.testing.assert_array_equal(mesh.vertices, saved.vertices)
    image = evaluator.output("picture", "image")
    assert image.shape == (48, 64, 4) and image.dtype == np.uint8
    assert evaluator.output("move", "no_such_port") is None


def test_reevaluating_recomputes_only_what_a_change_reaches(tmp_path):
    graph = sphere_graph()
    evaluator = geobrush.Evaluator()
    evaluator.evaluate(graph, out_dir=tmp_path)
    assert evaluator.compute_count == 3
    again = evaluator.evaluate(graph, out_dir=tmp_path)
    assert again.computed == 0 and again.cache_hits == 3
    graph.set("move", "translate", (0, 0, 0))
    changed = evaluator.evaluate(graph, out_dir=tmp_path)
    assert {run.node for run in changed.runs if not run.cache_hit} == {"move", "save"}
    assert evaluator.compute_count == 5
    centre = geobrush.read_mesh(tmp_path / "sphere.obj").vertices.mean(axis=0)
    np.testing.assert_allclose(centre, 0, atol=1e-12)


def test_params_read_and_set_with_their_kinds():
    graph = sphere_graph()
    assert graph.get("move", "translate") == (1.0, 2.0, 3.0)
    assert graph["shape.resolution"] == 8
    assert graph["shape.minor_radius"] == 0.25  # its default
    graph["shape.size"] = 3  # an int where a double is declared
    assert graph["shape.size"] == 3.0 and isinstance(graph["shape.size"], float)
    graph.assign("shape.shape=torus")
    assert graph.params("shape")["shape"] == "torus"
    assert graph.node_type("shape") == "geobrush.primitive"
    assert ("move.mesh", "save.mesh") in graph.connections


@pytest.mark.parametrize(
    "edit, node, where, message",
    [
        (lambda g: g.set("shape", "size", -1), "shape", "param 'size'", "outside"),
        (lambda g: g.set("shape", "shape", "cone"), "shape", "param 'shape'", "cone"),
        (lambda g: g.set("shape", "size", "big"), "shape", "param 'size'", "string"),
        (lambda g: g.set("shape", "colour", 1), "shape", "param 'colour'", "no such parameter"),
        (lambda g: g.set("move", "translate", (1, 2)), "move", "param 'translate'", ""),
        (lambda g: g.add_node("x", "geobrush.nothing"), "x", None, "unknown node type"),
        (lambda g: g.add_node("shape", "geobrush.primitive"), "shape", None, "exists"),
        (lambda g: g.connect("shape.mesh", "move.no_port"), "move", None, "no_port"),
        (lambda g: g.connect("save.mesh", "move.mesh"), "save", "output 'mesh'", "no such output"),
        (lambda g: g.disconnect("shape.mesh"), "shape", "input 'mesh'", "not connected"),
    ],
)
def test_a_rejected_edit_raises_graph_error_and_changes_nothing(edit, node, where, message):
    graph = sphere_graph()
    before = graph.to_json()
    with pytest.raises(geobrush.GraphError) as error:
        edit(graph)
    assert message in str(error.value)
    assert error.value.node == node
    if where is not None:
        assert error.value.where == where
    assert graph.to_json() == before


def test_an_incomplete_graph_cannot_be_evaluated():
    graph = geobrush.Graph()
    graph.add_node("move", "geobrush.transform")
    with pytest.raises(geobrush.GraphError, match="mesh"):
        graph.check()
    with pytest.raises(geobrush.GraphError):
        geobrush.Evaluator().evaluate(graph)


def test_a_failing_node_raises_evaluation_error_and_writes_nothing(tmp_path):
    graph = geobrush.Graph()
    graph.add_node("load", "geobrush.load_mesh", path=str(tmp_path / "missing.obj"))
    graph.add_node("save", "geobrush.save_mesh", path="out.obj")
    graph.connect("load.mesh", "save.mesh")
    with pytest.raises(geobrush.EvaluationError) as error:
        geobrush.Evaluator().evaluate(graph, out_dir=tmp_path)
    assert error.value.node == "load"
    assert "missing.obj" in str(error.value)
    assert not error.value.report.ok
    assert not (tmp_path / "out.obj").exists()
    report = geobrush.Evaluator().evaluate(graph, out_dir=tmp_path, check=False)
    assert not report.ok and "missing.obj" in report.error


def test_graph_files_load_save_and_run_as_the_command_runs_them(source_dir, tmp_path):
    graph = geobrush.Graph.load(source_dir / "graphs" / "default.json")
    assert graph.file.endswith("default.json")
    saved = tmp_path / "copy.json"
    graph.save(saved)
    assert json.loads(saved.read_text())["format"] == "geobrush-graph"
    report = geobrush.Evaluator().evaluate(geobrush.Graph.load(saved), out_dir=tmp_path / "out")
    assert {p.name for p in report.files_written} == {"default.obj", "default.png"}
    with pytest.raises(geobrush.GraphError) as error:
        geobrush.Graph.load(tmp_path / "none.json")
    assert error.value.file.endswith("none.json")


def test_metrics_and_targets(source_dir, tmp_path):
    graph = geobrush.Graph.load(source_dir / "graphs" / "compare_mountain_sphere_membrane.json")
    evaluator = geobrush.Evaluator()
    partial = evaluator.evaluate(graph, out_dir=tmp_path, targets=["target_mesh"])
    assert [run.node for run in partial.runs] == ["target_mesh"]
    report = evaluator.evaluate(graph, out_dir=tmp_path)
    assert report.metrics["metrics.new_self_intersections"] == 0
    assert report.metrics["metrics.manifold"] == 1
    assert evaluator.output("metrics", "metrics")["manifold"] == 1


def test_progress_reaches_python_and_its_exception_stops_the_evaluation(tmp_path):
    graph = sphere_graph()
    seen = []
    geobrush.Evaluator().evaluate(
        graph, out_dir=tmp_path, progress=lambda node, fraction: seen.append((node, fraction)))
    assert {node for node, _ in seen} == {"shape", "move", "save"}
    assert all(0 <= fraction <= 1 for _, fraction in seen)

    def stop(node, fraction):
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        geobrush.Evaluator().evaluate(sphere_graph("stopped.obj"), out_dir=tmp_path, progress=stop)
    assert not (tmp_path / "stopped.obj").exists()


def test_node_types_list_the_plugins():
    types = {t["id"]: t for t in geobrush.node_types()}
    assert "geobrush.primitive" in types
    size = types["geobrush.primitive"]["params"]["size"]
    assert size["kind"] == "double" and size["default"] == 1.0
    assert geobrush.plugin_errors() == []
    assert set(geobrush.methods()) >= {"geobrush", "variational"}


def test_one_evaluator_serves_several_threads(tmp_path):
    import threading
    evaluator = geobrush.Evaluator()
    reports, errors = [], []

    def run(index):
        try:
            graph = sphere_graph(f"sphere{index}.obj")
            graph.set("move", "translate", (index, 0, 0))
            reports.append(evaluator.evaluate(graph, out_dir=tmp_path, progress=lambda n, f: None))
        except Exception as error:  # reported below
            errors.append(error)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == [] and len(reports) == 4
    for index in range(4):
        centre = geobrush.read_mesh(tmp_path / f"sphere{index}.obj").vertices.mean(axis=0)
        np.testing.assert_allclose(centre, (index, 0, 0), atol=1e-12)


def test_vertex_fields_come_as_arrays_by_name(tmp_path):
    """emd_signal and emd on a relief plane: the modes as NumPy arrays that sum back to g."""
    graph = geobrush.Graph()
    graph.add_node("plane", "geobrush.primitive", shape="plane", resolution=40, relief=0.05)
    graph.add_node("signal", "geobrush.emd_signal")
    graph.add_node("modes", "geobrush.emd")
    graph.connect("plane.mesh", "signal.mesh")
    graph.connect("plane.mesh", "modes.mesh")
    graph.connect("signal.signal", "modes.signal")
    evaluator = geobrush.Evaluator()
    assert evaluator.evaluate(graph, out_dir=tmp_path).ok
    signal = evaluator.output("signal", "signal")
    modes = evaluator.output("modes", "modes")
    assert list(signal) == ["g", "area"]
    assert list(modes) == ["h1", "h2", "h3", "r"]
    vertices = evaluator.output("plane", "mesh").vertices.shape[0]
    assert all(column.shape == (vertices,) and column.dtype == np.float64 for column in modes.values())
    np.testing.assert_allclose(sum(modes.values()), signal["g"], rtol=0, atol=1e-12)
