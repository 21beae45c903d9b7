"""The contact law catalogue from Python: the scene spelling of stiffness and dissipation."""

import numpy as np
import pytest

import jointwear
from conftest import STANDARD, short

JOHNSON_FLORES = {
    "stiffness": "johnson",
    "dissipation": "flores",
    "restitution": 0.9,
    "grazing_velocity_m_s": 1e-3,
}


def test_contact_laws_the_paper_law_is_named_by_its_pair():
    (joint,) = jointwear.Scene.load(STANDARD).check()["joints"]
    assert (joint["stiffness"], joint["dissipation"]) == ("hybrid", "zhiying-qishao")


def test_contact_laws_any_pair_runs_from_python_and_changes_the_wear():
    scene = short(jointwear.Scene.load(STANDARD)).set("clearance.0.contact", JOHNSON_FLORES)
    (joint,) = scene.check()["joints"]
    assert (joint["stiffness"], joint["dissipation"]) == ("johnson", "flores")
    wear = scene.run().wear["rod-slider"]
    paper = short(jointwear.Scene.load(STANDARD)).run().wear["rod-slider"]
    assert np.all(np.isfinite(wear)) and wear.max() > 0
    # Johnson's law is about 4 times stiffer than the paper's at 1 µm: another orbit, other wear.
    assert not np.array_equal(wear, paper)


def test_contact_laws_a_model_and_a_pair_are_refused_naming_the_table():
    with pytest.raises(jointwear.SceneError, match=r"clearance\[0\]\.contact.*not both"):
        jointwear.Scene.load(STANDARD).set("clearance.0.contact.stiffness", "johnson").check()


def test_contact_laws_an_unknown_law_is_refused():
    with pytest.raises(jointwear.SceneError, match="johnsen"):
        jointwear.Scene.load(STANDARD).set("clearance.0.contact.stiffness", "johnsen").check()
