"""Errors are Python exceptions with their location: maille.SceneError, maille.BlowUp,
maille.CheckpointError; never a crash of the interpreter."""
import numpy as np
import pytest

import maille
from conftest import CHAIN, DATA, EXAMPLES, FLAG, UNSTABLE


def test_scene_error_has_file_line_key():
    with pytest.raises(maille.SceneError) as e:
        maille.Simulation(DATA / "bad" / "negative_mass.toml")
    err = e.value
    assert err.file.endswith("negative_mass.toml")
    assert err.line == 4 and err.column == 8
    assert err.key == "mass[0].mass"
    assert "must be > 0" in err.message
    assert str(err).startswith(err.file + ":4:8: error: key 'mass[0].mass'")
    assert isinstance(err, ValueError) and isinstance(err, maille.Error)


def test_missing_file():
    with pytest.raises(maille.SceneError) as e:
        maille.Simulation("/nonexistent/scene.toml")
    assert "/nonexistent/scene.toml" in str(e.value)


def test_bad_override_names_the_key():
    with pytest.raises(maille.SceneError) as e:
        maille.Simulation(FLAG, overrides={"simulation.step": "fast"})
    assert e.value.key == "simulation.step"
    with pytest.raises(maille.SceneError) as e:
        maille.Simulation(FLAG, overrides={"flag[0].stiffnes": 3.0})
    assert e.value.key == "flag[0].stiffnes" and "unknown key" in str(e.value)
    with pytest.raises(maille.SceneError) as e:
        maille.Simulation(FLAG, threads=0)
    assert e.value.key == "threads"


def test_live_set_is_validated_like_set():
    sim = maille.Simulation(FLAG)
    sim.step(10)
    before = sim.state_hash()
    with pytest.raises(maille.SceneError) as e:
        sim.set("flag[0].stiffness", -5.0)
    assert e.value.key == "flag[0].stiffness"
    assert "must be >= 0" in str(e.value)
    with pytest.raises(maille.SceneError) as e:
        sim.set("fields.wind.velocity", [1.0, 2.0])
    assert e.value.key == "fields.wind.velocity"
    with pytest.raises(maille.SceneError) as e:
        sim.set("simulation.output_every", 5)
    assert e.value.key == "simulation.output_every"
    assert sim.state_hash() == before  # refused edits change nothing
    sim.step(10)


def test_live_set_changes_the_run():
    a = maille.Simulation(FLAG)
    b = maille.Simulation(FLAG)
    a.set("fields.wind.velocity", [4.0, 0.0, 1.0])
    a.step(200)
    b.step(200)
    assert a.state_hash() != b.state_hash()
    # the same edit given at construction is the same run
    c = maille.Simulation(FLAG, overrides={"fields.wind.velocity": [4.0, 0.0, 1.0]})
    c.step(200)
    assert np.array_equal(a.positions, c.positions)
    # keys the model's fingerprint leaves out, and a stage's table, take effect too
    for key, value in [("fields.wind.gust_frequency", 2.0), ("fields.wind.density", 1.0)]:
        d = maille.Simulation(FLAG)
        d.set(key, value)
        d.step(200)
        assert d.state_hash() != b.state_hash(), key
        e = maille.Simulation(FLAG, overrides={key: value})
        e.step(200)
        assert e.state_hash() == d.state_hash(), key
    a.set("simulation.step", 1e-4)
    assert a.step_size == 1e-4
    a.set("simulation.integrator", "symplectic_euler")
    assert a.integrator == "symplectic_euler"
    a.step(10)


def test_live_set_of_the_implicit_settings():
    """[simulation.implicit] is live (Simulator::set_implicit, as the viewer's controls): a live
    edit gives the run that the same keys at construction give; it was once ignored."""
    keys = {"simulation.integrator": "implicit_euler", "simulation.step": 1.0 / 120,
            "simulation.implicit.solver": "vbd"}
    a = maille.Simulation(FLAG, overrides=keys)
    b = maille.Simulation(FLAG, overrides=keys)
    c = maille.Simulation(FLAG, overrides={**keys, "simulation.implicit.iterations": 3,
                                           "simulation.implicit.coarse": "off"})
    a.set("simulation.implicit.iterations", 3)
    a.set("simulation.implicit.coarse", "off")
    for s in (a, b, c):
        s.step(20)
    assert a.state_hash() == c.state_hash()
    assert a.state_hash() != b.state_hash()
    assert a.stats()["solver_iterations"] == 3
    with pytest.raises(maille.SceneError) as e:
        a.set("simulation.implicit.coarse", "multigrid")
    assert e.value.key == "simulation.implicit.coarse"


def test_live_set_of_a_stage_key():
    """A stage's table (self-collision's radius: at 0.2 m contacts start at once) is a live key."""
    heap = EXAMPLES / "cloth_heap.toml"
    a = maille.Simulation(heap)
    b = maille.Simulation(heap)
    c = maille.Simulation(heap, overrides={"self_collision.radius": 0.2})
    a.set("self_collision.radius", 0.2)
    for s in (a, b, c):
        s.step(50)
    assert a.state_hash() != b.state_hash()
    assert a.state_hash() == c.state_hash()
    assert a.stats()["self_contacts"] > 0 and b.stats()["self_contacts"] == 0
    with pytest.raises(maille.SceneError) as e:
        a.set("self_collision.broad_phase", "quadtree")
    assert e.value.key == "self_collision.broad_phase"


def test_blow_up_raises_with_step_and_kind():
    sim = maille.Simulation(UNSTABLE)
    with pytest.raises(maille.BlowUp) as e:
        sim.run()
    err = e.value
    assert err.step == 3 and err.kind == "spring" and err.module == "spring"
    assert err.time == pytest.approx(0.45)
    assert "blow-up detected at step 3" in str(err)
    assert isinstance(err, RuntimeError)
    # stepping again reports it again; a reset clears it
    with pytest.raises(maille.BlowUp):
        sim.step()
    sim.reset()
    sim.step()


def test_model_argument_errors():
    m = maille.Model()
    with pytest.raises(maille.SceneError) as e:
        m.add_point([0, 0, 0], mass=-1)
    assert e.value.key == "mass" and e.value.file == "<maille.Model.add_point>"
    with pytest.raises(maille.SceneError) as e:
        m.add_point([0, 0], mass=1)
    assert e.value.key == "position"
    i = m.add_point([0, 0, 0])
    with pytest.raises(maille.SceneError) as e:
        m.add_link("spring_damper", i, 5, stiffness=1.0)
    assert e.value.key == "b" and "does not exist" in str(e.value)
    j = m.add_fixed_point([0, 1, 0])
    with pytest.raises(maille.SceneError) as e:
        m.add_link("elastic_band", i, j)
    assert e.value.key == "kind" and "spring_damper" in str(e.value)
    with pytest.raises(maille.SceneError) as e:
        m.add_link("spring_damper", i, j, stifness=1.0)
    assert e.value.key == "stifness"
    with pytest.raises(maille.SceneError) as e:
        m.add_link("spring_damper", i, j, damping=1.0)  # stiffness is required
    assert e.value.key == "stiffness" and "required" in str(e.value)
    with pytest.raises(maille.SceneError) as e:
        m.add_flag(resolution=[1, 1])
    assert e.value.key == "flag[0].resolution" and e.value.line > 0
    with pytest.raises(maille.SceneError) as e:
        m.set("fields.gravity", "down")
    assert e.value.key == "fields.gravity"
    with pytest.raises(maille.SceneError):
        maille.Simulation(maille.Model())  # no point
    with pytest.raises(maille.SceneError) as e:
        m.set("flag[0].stiffness", 3)
    assert e.value.key == "flag[0].stiffness"


def test_values_that_are_not_scene_values():
    sim = maille.Simulation(CHAIN)
    with pytest.raises(maille.SceneError) as e:
        sim.set("fields.gravity", object())
    assert e.value.key == "fields.gravity"


def test_checkpoint_of_another_scene_is_refused(tmp_path):
    a = maille.Simulation(CHAIN)
    a.step(5)
    a.save_checkpoint(str(tmp_path / "chain.bin"))
    b = maille.Simulation(FLAG)
    with pytest.raises(maille.CheckpointError) as e:
        b.load_checkpoint(str(tmp_path / "chain.bin"))
    assert e.value.file.endswith("chain.bin")
    c = maille.Simulation(CHAIN, step=5e-5)
    with pytest.raises(maille.CheckpointError) as e:
        c.load_checkpoint(str(tmp_path / "chain.bin"))
    assert "h = " in str(e.value)
    with pytest.raises(maille.CheckpointError):
        a.load_checkpoint(str(tmp_path / "missing.bin"))
    with pytest.raises(OSError):
        a.save_checkpoint("/proc/maille_cannot_write_here/c.bin")
