"""Shared fixtures: the repository, the CLI binary, a Cornell box scene file whose
film is float32 (so the CLI's EXR holds the render's exact values)."""

import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
CBOX = REPO / "scenes" / "cbox" / "cbox_path.xml"


def cli_binary():
    """The wavetrace CLI: $WAVETRACE_BIN, else the debug build in the target folder
    (CARGO_TARGET_DIR or the repository's target/)."""
    if os.environ.get("WAVETRACE_BIN"):
        return pathlib.Path(os.environ["WAVETRACE_BIN"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    return target / "debug" / "wavetrace"


@pytest.fixture(scope="session")
def cli():
    b = cli_binary()
    assert b.exists(), f"{b}: build the CLI first (cargo build), or set WAVETRACE_BIN"
    return b


@pytest.fixture(scope="session")
def cbox_f32(tmp_path_factory):
    """cbox_path.xml with absolute mesh paths and a float32 film."""
    text = CBOX.read_text()
    meshes = (CBOX.parent / "meshes").as_posix()
    text = text.replace('value="meshes/', f'value="{meshes}/')
    text = text.replace(
        '<rfilter type="box"/>',
        '<rfilter type="box"/>\n            <string name="component_format" value="float32"/>',
    )
    path = tmp_path_factory.mktemp("scenes") / "cbox_f32.xml"
    path.write_text(text)
    return path
