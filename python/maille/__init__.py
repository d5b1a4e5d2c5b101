"""Maille, a mass-interaction (mass-spring) physics engine: scenes, simulations and models built
in code, with positions and velocities as NumPy views of the engine's memory. docs/python.md
documents the API.

The engine is the compiled extension `maille._maille`; this file only chooses OpenMP's wait
policy before loading it. libgomp reads OMP_WAIT_POLICY once, when it is loaded with the
engine: unset, a thread waiting at a barrier spins, which is ruinous when another program keeps
a core busy (its partner is descheduled and the spin burns the time it needs: two threads beside
a busy core ran flag_64 60 times slower than one). So, as the `maille` command does, the policy
is set to passive when the cores are shared and the user set none: the rule is the engine's own
(include/maille/cores.hpp, asked through `maille._cores`, which does not load OpenMP). It stays
set in os.environ: it is this process's policy, and child processes inherit it as they inherit
the rest.
"""
import os as _os

if "OMP_WAIT_POLICY" not in _os.environ and "GOMP_SPINCOUNT" not in _os.environ:
    from . import _cores

    if _cores.passive_wait_advised():
        _os.environ["OMP_WAIT_POLICY"] = "passive"

from ._maille import *  # noqa: E402,F401,F403  (the API: docs/python.md)
from ._maille import __version__  # noqa: E402,F401
