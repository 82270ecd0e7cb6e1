"""Pictures: the exploded view (matplotlib, headless) and the HTML view (plotly)."""

import io

import numpy as np
import pytest

import penedge
from penedge import pictures

import shapes

pytest.importorskip("matplotlib")


def test_exploded_faces_move_blocks_away_from_the_centre():
    system = penedge.paper_example(1)
    parts = pictures.exploded_faces(system, explode=0.5)
    assert len(parts) == 8
    for block, (faces, normals, offset) in zip(system.blocks, parts, strict=True):
        assert np.allclose(offset, 0.5 * (block.centroid - [5, 5, 5]))
        assert len(faces) == len(block.faces) == len(normals)
        assert np.allclose(faces[0], block.vertices[block.faces[0]] + offset)
    still = pictures.exploded_faces(system, explode=0.0)
    assert all(np.allclose(offset, 0) for _, _, offset in still)


def test_block_colors_are_distinct():
    colors = pictures.block_colors(26)
    assert colors.shape == (26, 3)
    assert ((colors >= 0) & (colors <= 1)).all()
    assert len({tuple(np.round(c, 3)) for c in colors}) == 26


def test_plot_system_draws_one_collection_per_block():
    ax = pictures.plot_system(penedge.paper_example(3), title="Example 3")
    assert len(ax.collections) == 26
    assert ax.get_title() == "Example 3"


def test_plot_accepts_a_list_of_blocks_and_colours():
    ax = pictures.plot_system([shapes.cube()], colors=["red"], labels=True)
    assert len(ax.collections) == 1
    assert len(ax.texts) == 1


def test_save_picture_png_to_a_file_object():
    buffer = io.BytesIO()
    pictures.save_picture(penedge.paper_example(2), buffer, format="png", title="Example 2")
    assert buffer.getvalue().startswith(b"\x89PNG\r\n\x1a\n")


def test_save_picture_to_a_path(tmp_path):
    path = tmp_path / "ex.svg"
    pictures.save_picture(penedge.paper_example(1), path)
    assert path.read_text(encoding="utf-8").lstrip().startswith("<?xml")


def test_empty_system_draws_nothing():
    ax = pictures.plot_system(penedge.BlockSystem([]))
    assert len(ax.collections) == 0


def test_write_html(tmp_path):
    pytest.importorskip("plotly")
    path = tmp_path / "ex.html"
    pictures.write_html(penedge.paper_example(1), path, title="Example 1", include_plotlyjs="cdn")
    text = path.read_text(encoding="utf-8")
    assert "Example 1" in text
    assert text.count('"name":"block ') == 8
