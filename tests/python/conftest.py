"""Where the suite finds the shipped meshes, the command and the sources (set by ctest)."""

import os
import pathlib

import pytest


def _path(variable):
    value = os.environ.get(variable)
    if not value:
        pytest.exit(f"{variable} is not set: run the suite through ctest", returncode=2)
    return pathlib.Path(value)


@pytest.fixture(scope="session")
def meshes():
    return _path("GEOBRUSH_MESH_DIR")


@pytest.fixture(scope="session")
def cli():
    return _path("GEOBRUSH_CLI")


@pytest.fixture(scope="session")
def source_dir():
    return _path("GEOBRUSH_SOURCE_DIR")
