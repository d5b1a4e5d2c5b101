"""render(): a headless PNG of the current state, like `maille render`'s still."""
import struct

import pytest

import maille
from conftest import FLAG


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


@pytest.mark.skipif(not maille.render_available, reason="built without rendering")
def test_render_writes_a_png(tmp_path):
    sim = maille.Simulation(FLAG)
    sim.step(200)
    before = sim.state_hash()
    out = tmp_path / "still.png"
    sim.render(str(out), width=160, height=90)
    assert png_size(out) == (160, 90)
    sim.render(str(tmp_path / "sub" / "cam.png"), width=64, height=48, camera=(60, 30, 0.8),
               samples=1, mesh=True)
    assert png_size(tmp_path / "sub" / "cam.png") == (64, 48)
    assert sim.state_hash() == before  # drawing does not touch the state
    with pytest.raises(maille.SceneError) as e:
        sim.render(str(tmp_path / "x.mp4"))
    assert e.value.key == "path"
    with pytest.raises(maille.SceneError) as e:
        sim.render(str(tmp_path / "x.png"), width=0)
    assert e.value.key == "width"


@pytest.mark.skipif(maille.render_available, reason="built with rendering")
def test_render_says_it_is_not_built(tmp_path):
    with pytest.raises(RuntimeError, match="without rendering"):
        maille.Simulation(FLAG).render(str(tmp_path / "still.png"))
