"""Exceptions raised by the geobrush module.

Each carries what it concerns as attributes: ``file`` (the graph or mesh file, or None),
``node`` (the node's name, or None) and ``where`` (the port or param, e.g. "param 'radius'", or
None). An EvaluationError also carries the evaluation's ``report``.
"""


class Error(Exception):
    """A GeoBrush error; its text is one line naming the file, node and port."""

    def __init__(self, message, file=None, node=None, where=None, report=None):
        super().__init__(message)
        self.file = file or None
        self.node = node or None
        self.where = where or None
        self.report = report


class GraphError(Error, ValueError):
    """A graph, a param value or an argument that cannot be used."""


class MeshError(Error, ValueError):
    """A mesh file or array that cannot be used."""


class EvaluationError(Error, RuntimeError):
    """A node failed while evaluating a graph; nothing was written."""
