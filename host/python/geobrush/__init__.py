"""GeoBrush: clone 3D surface geometry with node graphs, from Python.

The same node graphs, plugins and evaluator as the ``geobrush`` command::

    import geobrush
    result = geobrush.clone("source.obj", (0, 0.2, 0.1), 0.05, "target.obj", (1, 0, 0))
    vertices, faces = result.mesh.vertices, result.mesh.faces

See help(geobrush.Graph), help(geobrush.Evaluator), help(geobrush.Mesh), help(geobrush.clone).
"""

from .errors import Error, EvaluationError, GraphError, MeshError
from ._geobrush import (
    CloneResult,
    Evaluator,
    Graph,
    Mesh,
    NodeRun,
    Report,
    Value,
    clone,
    methods,
    node_types,
    plugin_errors,
    read_mesh,
    __version__,
)

__all__ = [
    "CloneResult",
    "Error",
    "EvaluationError",
    "Evaluator",
    "Graph",
    "GraphError",
    "Mesh",
    "MeshError",
    "NodeRun",
    "Report",
    "Value",
    "clone",
    "methods",
    "node_types",
    "plugin_errors",
    "read_mesh",
]
