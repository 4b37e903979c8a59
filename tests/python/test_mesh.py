"""geobrush.Mesh: NumPy arrays in and out, files read and written as the nodes do."""

import numpy as np
import pytest

import geobrush

# A regular tetrahedron, outward oriented.
TETRA_VERTICES = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)
TETRA_FACES = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])


def test_arrays_round_trip_exactly():
    mesh = geobrush.Mesh(TETRA_VERTICES, TETRA_FACES)
    assert mesh.vertex_count == 4 and mesh.face_count == 4
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape == (4, 3)
    assert mesh.faces.dtype == np.int64 and mesh.faces.shape == (4, 3)
    np.testing.assert_array_equal(mesh.vertices, TETRA_VERTICES)
    # The same triangles, each possibly starting at another corner.
    def canonical(faces):
        return sorted(tuple(np.roll(f, -int(np.argmin(f)))) for f in faces)
    assert canonical(mesh.faces) == canonical(TETRA_FACES)
    stats = mesh.stats()
    assert stats["euler_characteristic"] == 2
    assert stats["boundary_loops"] == 0 and stats["components"] == 1


def test_arrays_are_copies():
    mesh = geobrush.Mesh(TETRA_VERTICES, TETRA_FACES)
    vertices = mesh.vertices
    vertices[0] = 42
    assert mesh.vertices[0, 0] == 1


def test_any_number_type_is_accepted():
    mesh = geobrush.Mesh(TETRA_VERTICES.astype(np.float32), TETRA_FACES.astype(np.int32))
    np.testing.assert_array_equal(mesh.vertices, TETRA_VERTICES)
    assert geobrush.Mesh(TETRA_VERTICES.tolist(), TETRA_FACES.tolist()).face_count == 4


@pytest.mark.parametrize(
    "vertices, faces, message",
    [
        (TETRA_VERTICES[:, :2], TETRA_FACES, "vertices: expected an array of shape (n, 3)"),
        (TETRA_VERTICES, TETRA_FACES[:, :2], "faces: expected an array of shape (n, 3)"),
        (TETRA_VERTICES, [[0, 1, 4]], "triangle 0 names vertex 4 of 4"),
        (TETRA_VERTICES, [[0, 1, -1]], "triangle 0 names vertex -1 of 4"),
        (TETRA_VERTICES, [[0, 1, 1]], "triangle 0 repeats a vertex"),
        ([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]], [[0, 1, 2]], "vertex 1 has a non-finite"),
        (TETRA_VERTICES, np.zeros((0, 3), dtype=int), "no faces"),
        # A third triangle on edge 0-1.
        (np.vstack([TETRA_VERTICES, [[3, 3, 3]]]),
         np.vstack([TETRA_FACES, [[0, 1, 4]]]), "non-manifold"),
    ],
)
def test_bad_arrays_raise_mesh_error(vertices, faces, message):
    with pytest.raises(geobrush.MeshError) as error:
        geobrush.Mesh(vertices, faces)
    assert message in str(error.value)
    assert isinstance(error.value, ValueError)


def test_non_manifold_triangles_are_split_off_when_repaired():
    vertices = np.vstack([TETRA_VERTICES, [[3, 3, 3]]])
    faces = np.vstack([TETRA_FACES, [[0, 1, 4]]])
    with pytest.warns(UserWarning, match="repaired 1 face"):
        mesh = geobrush.Mesh(vertices, faces, repair=True)
    assert mesh.face_count == 5


def test_files_read_and_write_as_the_nodes_do(meshes, tmp_path):
    sphere = geobrush.read_mesh(meshes / "sphere.obj")
    assert sphere.stats()["euler_characteristic"] == 2
    # On the unit sphere, every vertex at distance 1.
    np.testing.assert_allclose(np.linalg.norm(sphere.vertices, axis=1), 1, atol=1e-6)
    sphere.write(tmp_path / "copy.obj")
    again = geobrush.read_mesh(tmp_path / "copy.obj")
    np.testing.assert_array_equal(again.vertices, sphere.vertices)
    np.testing.assert_array_equal(again.faces, sphere.faces)
    # A mesh made in Python, written as PLY and read back.
    geobrush.Mesh(sphere.vertices * 2, sphere.faces).write(str(tmp_path / "big.ply"))
    big = geobrush.read_mesh(str(tmp_path / "big.ply"))
    np.testing.assert_allclose(big.vertices, 2 * sphere.vertices, rtol=1e-7)


def test_file_errors_name_the_file(tmp_path):
    with pytest.raises(geobrush.MeshError, match="missing.obj"):
        geobrush.read_mesh(tmp_path / "missing.obj")
    (tmp_path / "broken.off").write_text("OFF\n3 1 0\n0 0 0\n")
    with pytest.raises(geobrush.MeshError, match="broken.off"):
        geobrush.read_mesh(tmp_path / "broken.off")
    mesh = geobrush.Mesh(TETRA_VERTICES, TETRA_FACES)
    with pytest.raises(geobrush.MeshError, match="unknown mesh format"):
        mesh.write(tmp_path / "mesh.xyz")
    assert not (tmp_path / "mesh.xyz").exists()
