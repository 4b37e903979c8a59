// geobrush.Mesh: meshes as NumPy arrays and back, read and written as the nodes do.
#include <pybind11/numpy.h>
#include <pybind11/stl/filesystem.h>

#include <span>

#include "bindings.hpp"
#include "geobrush/mesh_io.hpp"

namespace geobrush::python {
namespace {

using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Triangles = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

void requireRowsOfThree(const py::array& array, const char* name) {
  if (array.ndim() == 2 && array.shape(1) == 3) return;
  std::string shape;
  for (py::ssize_t d = 0; d < array.ndim(); ++d)
    shape += (d ? ", " : "") + std::to_string(array.shape(d));
  raise("MeshError",
        std::string(name) + ": expected an array of shape (n, 3), got (" + shape + ")");
}

PyMesh meshFromPython(const Positions& vertices, const Triangles& faces, bool repair) {
  requireRowsOfThree(vertices, "vertices");
  requireRowsOfThree(faces, "faces");
  MeshReadOptions options;
  options.repairNonManifold = repair;
  MeshReadResult result;
  {
    py::gil_scoped_release unlocked;
    result = meshFromArrays(std::span(vertices.data(), std::size_t(vertices.size())),
                            std::span(faces.data(), std::size_t(faces.size())), "arrays", options);
  }
  for (const auto& warning : result.warnings)
    PyErr_WarnEx(PyExc_UserWarning, warning.c_str(), 1);
  return {std::move(result.mesh)};
}

py::array_t<double> verticesOf(const PyMesh& self) {
  const TriMesh& surface = self.mesh->surface;
  py::array_t<double> array({py::ssize_t(surface.n_vertices()), py::ssize_t(3)});
  auto out = array.mutable_unchecked<2>();
  for (auto v : surface.vertices())
    for (int k = 0; k < 3; ++k)
      out(v.idx(), k) = surface.point(v)[k];
  return array;
}

py::array_t<std::int64_t> facesOf(const PyMesh& self) {
  const TriMesh& surface = self.mesh->surface;
  py::array_t<std::int64_t> array({py::ssize_t(surface.n_faces()), py::ssize_t(3)});
  auto out = array.mutable_unchecked<2>();
  for (auto f : surface.faces()) {
    int k = 0;
    for (auto v : surface.fv_range(f))
      out(f.idx(), k++) = v.idx();
  }
  return array;
}

py::dict statsOf(const PyMesh& self) {
  const MeshStats stats = meshStats(self.mesh->surface);
  return py::dict(py::arg("vertices") = stats.vertices, py::arg("faces") = stats.faces,
                  py::arg("boundary_loops") = stats.boundaryLoops,
                  py::arg("components") = stats.components,
                  py::arg("isolated_vertices") = stats.isolatedVertices,
                  py::arg("euler_characteristic") = stats.eulerCharacteristic);
}

PyMesh readFromPython(const std::filesystem::path& path, bool repair) {
  MeshReadOptions options;
  options.repairNonManifold = repair;
  MeshReadResult result;
  {
    py::gil_scoped_release unlocked;
    result = readMesh(path, options);
  }
  for (const auto& warning : result.warnings)
    PyErr_WarnEx(PyExc_UserWarning, warning.c_str(), 1);
  return {std::move(result.mesh)};
}

}  // namespace

void bindMesh(py::module_& module) {
  py::class_<PyMesh>(module, "Mesh",
                     "An immutable triangle mesh. Mesh(vertices, faces) builds one from an (n, 3) "
                     "array of positions and an (m, 3) array of 0-based vertex indices.")
      .def(py::init(&meshFromPython), py::arg("vertices"), py::arg("faces"), py::kw_only(),
           py::arg("repair") = false,
           "Raises MeshError for a bad shape, a non-finite position, an index out of range, a "
           "triangle repeating a vertex, or (unless repair) non-manifold triangles.")
      .def_property_readonly("vertices", &verticesOf,
                             "Positions, an (n, 3) float64 array (a copy).")
      .def_property_readonly("faces", &facesOf, "Triangles, an (m, 3) int64 array (a copy).")
      .def_property_readonly("vertex_count",
                             [](const PyMesh& self) { return self.mesh->surface.n_vertices(); })
      .def_property_readonly("face_count",
                             [](const PyMesh& self) { return self.mesh->surface.n_faces(); })
      .def("stats", &statsOf, "Counts: vertices, faces, boundary loops, components, Euler char.")
      .def(
          "write",
          [](const PyMesh& self, const std::filesystem::path& path) {
            py::gil_scoped_release unlocked;
            writeMeshFile(*self.mesh, path);
          },
          py::arg("path"),
          "Writes OBJ, PLY, OFF or STL by extension, atomically. Raises MeshError.")
      .def("__repr__",
           [](const PyMesh& self) { return "<geobrush.Mesh " + self.mesh->summary() + ">"; });
  module.def("read_mesh", &readFromPython, py::arg("path"), py::kw_only(),
             py::arg("repair") = false,
             "Reads OBJ, PLY, OFF or STL into a Mesh, as the load_mesh node does; what it "
             "repaired or dropped comes as warnings. Raises MeshError naming the file.");
}

}  // namespace geobrush::python
