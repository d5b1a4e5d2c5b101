"""Contacts between groups ([[contact]], a broad-phase stage) retuned live: setting a contact's
stiffness mid-run gives the run that had it from the start, as for the other stage tables."""
import maille
from conftest import EXAMPLES

JELLY = EXAMPLES / "jelly_cube_bounce.toml"
LOW = {"lattice[0].origin": [-0.25, 0.06, -0.25]}  # its bottom inside the floor's reach


def test_live_set_of_a_contact_key():
    a = maille.Simulation(JELLY, overrides=LOW)
    b = maille.Simulation(JELLY, overrides=LOW)
    c = maille.Simulation(JELLY, overrides={**LOW, "contact[0].stiffness": 6000.0})
    a.set("contact[0].stiffness", 6000.0)
    for s in (a, b, c):
        s.step(300)
    assert a.state_hash() == c.state_hash()
    assert a.state_hash() != b.state_hash()
    assert "group_contact_candidates" in a.stats()
