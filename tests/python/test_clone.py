"""geobrush.clone(): the command's clone from Python, with the same arguments and results."""

import subprocess
import sys

import numpy as np
import pytest

import geobrush

MOUNTAIN = dict(source_point=(0.068548, 19.73209, 0.029055), radius=6.0,
                target_point=(0, 0, 1), scale=0.05)


def mountain_on_sphere(meshes, tmp_path, **options):
    return geobrush.clone(meshes / "mountain.obj", MOUNTAIN["source_point"], MOUNTAIN["radius"],
                          meshes / "sphere.obj", MOUNTAIN["target_point"],
                          scale=MOUNTAIN["scale"], output=tmp_path / "clone.obj", **options)


def test_the_same_clone_as_the_command_bit_for_bit(meshes, cli, tmp_path):
    result = mountain_on_sphere(meshes, tmp_path)
    command = subprocess.run(
        [str(cli), "clone", "--source", str(meshes / "mountain.obj"), "--source-point",
         "0.068548,19.73209,0.029055", "--radius", "6", "--target", str(meshes / "sphere.obj"),
         "--target-point", "0,0,1", "--scale", "0.05", "-o", str(tmp_path / "command.obj"),
         "--quiet"], capture_output=True, text=True)
    assert command.returncode == 0, command.stderr
    assert (tmp_path / "clone.obj").read_bytes() == (tmp_path / "command.obj").read_bytes()
    # A valid paste: one closed manifold piece of the sphere's genus, no new self-intersections.
    assert result.metrics["metrics.manifold"] == 1
    assert result.metrics["metrics.new_self_intersections"] == 0
    stats = result.mesh.stats()
    assert stats["components"] == 1 and stats["boundary_loops"] == 0
    assert stats["euler_characteristic"] == 2
    np.testing.assert_array_equal(result.mesh.vertices,
                                  geobrush.read_mesh(tmp_path / "clone.obj").vertices)
    # The target point was on the sphere already; the source point is snapped onto the mountain.
    np.testing.assert_allclose(result.target_point, (0, 0, 1), atol=1e-3)


def test_the_saved_graph_runs_to_the_same_mesh(meshes, tmp_path):
    result = mountain_on_sphere(meshes, tmp_path, save_graph=tmp_path / "clone.json",
                                image=tmp_path / "clone.png")
    assert (tmp_path / "clone.png").exists()
    graph = geobrush.Graph.load(tmp_path / "clone.json")
    evaluator = geobrush.Evaluator()
    graph["save_result.path"] = str(tmp_path / "again.obj")
    graph["render_result.path"] = str(tmp_path / "again.png")
    evaluator.evaluate(graph)
    assert (tmp_path / "again.obj").read_bytes() == (tmp_path / "clone.obj").read_bytes()
    assert result.graph.get("target_map", "scale") == 0.05


def test_sets_and_a_shared_evaluator(meshes, tmp_path):
    evaluator = geobrush.Evaluator()
    first = mountain_on_sphere(meshes, tmp_path, evaluator=evaluator,
                               set={"membrane.tolerance": 1e-7})
    assert first.graph["membrane.tolerance"] == 1e-7
    computed = evaluator.compute_count
    # Another angle: the source side (its canvas, DEM and cage) comes from the cache.
    second = geobrush.clone(meshes / "mountain.obj", MOUNTAIN["source_point"], 6.0,
                            meshes / "sphere.obj", (0, 0, 1), scale=0.05, angle=30,
                            output=tmp_path / "turned.obj", evaluator=evaluator,
                            set=["membrane.tolerance=1e-7"])
    cached = {run.node for run in second.report.runs if run.cache_hit}
    assert {"source_mesh", "source_canvas", "source_map"} <= cached
    assert evaluator.compute_count - computed < len(second.report.runs)
    assert second.metrics["metrics.new_self_intersections"] == 0


@pytest.mark.parametrize(
    "change, error, node, message",
    [
        (dict(source="missing.obj"), geobrush.GraphError, None, "source: "),
        (dict(radius=-1.0), geobrush.GraphError, "strokes", "radius must be positive"),
        (dict(method="none"), geobrush.GraphError, None, "no clone method 'none'"),
        (dict(set={"membrane.tolerance": -1}), geobrush.GraphError, "membrane", "tolerance"),
        (dict(set=["nothing.x=1"]), geobrush.GraphError, "nothing", ""),
        (dict(target_point=(0, 0)), geobrush.GraphError, None, "target_point"),
        # A paste larger than the whole target: the target canvas would wrap around the sphere.
        (dict(scale=5.0), geobrush.EvaluationError, "target_map", "wrap"),
    ],
)
def test_bad_arguments_raise_and_write_nothing(meshes, tmp_path, change, error, node, message):
    args = dict(source=meshes / "mountain.obj", source_point=MOUNTAIN["source_point"],
                radius=6.0, target=meshes / "sphere.obj", target_point=(0, 0, 1))
    options = dict(scale=0.05, output=tmp_path / "clone.obj", image=tmp_path / "clone.png",
                   save_graph=tmp_path / "clone.json")
    for key, value in change.items():
        (args if key in args else options)[key] = value
    if args["source"] == "missing.obj":
        args["source"] = tmp_path / "missing.obj"
    with pytest.raises(error) as raised:
        geobrush.clone(*args.values(), **options)
    assert message in str(raised.value)
    assert raised.value.node == node
    assert list(tmp_path.iterdir()) == []


def test_the_readme_batch_script(meshes, source_dir, tmp_path):
    folder = tmp_path / "targets"
    folder.mkdir()
    for name in ("sphere.obj", "cube.obj"):
        (folder / name).write_bytes((meshes / name).read_bytes())
    script = source_dir / "host" / "python" / "examples" / "clone_onto_folder.py"
    run = subprocess.run(
        [sys.executable, str(script), str(meshes / "mountain.obj"), "0.068548,19.73209,0.029055",
         "6", str(folder), str(tmp_path / "out")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [
        line for line in run.stdout.splitlines() if line.endswith(" 0 new self-intersections")]
    assert len(run.stdout.splitlines()) == 2
    for name in ("sphere", "cube"):
        assert (tmp_path / "out" / f"{name}.obj").exists()
        assert (tmp_path / "out" / f"{name}.png").exists()
