"""The composed cam types (camgen.kinds.get_kind) follow the registries: a kind composed before a
follower, form or motion is registered or removed is composed again after it (the registries'
state stamp, camgen.registry.generation), so a scene is read against the entries registered now."""
from __future__ import annotations

import pytest

SEGMENTS = [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 10.0}, {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -10.0}]


def _scene(follower: str) -> dict:
    cam = {"kind": "motion_law", "segments": SEGMENTS, "base_radius_mm": 30.0, "follower": follower}
    if follower == "flat_disc":
        cam["face_radius_mm"] = 60.0
    return {"cams": {"c": cam}}


def _follower():
    from camgen.followers import FollowerKind
    from camgen.schema import Key, Length

    return FollowerKind("flat_disc", "a stem ending in a circular face", "point",
                        (Key("face_radius_mm", Length(), "Radius of the face.", ("profile", "pitch"), default=50.0),),
                        radius=lambda parsed: parsed["face_radius"], has_radius=True)


def test_a_follower_registered_after_the_kind_was_composed_is_read_and_forgotten_when_removed():
    """The plate kind of motion_law, composed (and kept) before, reads a follower registered later and its
    key; after unregister the same scene is refused naming the follower or its key, and a scene with a package
    follower is read again (the kind composed a third time: all three reads answer the registry of their time)."""
    from camgen.errors import ParameterError, SceneError
    from camgen.followers import register, unregister
    from camgen.kinds import get_kind
    from camgen.scene import parse_scene

    before = get_kind("motion_law")
    assert get_kind("motion_law") is before  # nothing registered in between: the kind kept
    parse_scene(_scene("roller"), "t")
    with pytest.raises((ParameterError, SceneError), match="face_radius_mm|flat_disc"):
        parse_scene(_scene("flat_disc"), "t")
    register(_follower())
    try:
        assert get_kind("motion_law") is not before
        scene = parse_scene(_scene("flat_disc"), "t")
        assert (scene.cams[0].params.follower.kind, scene.cams[0].params.follower.roller_radius) == ("flat_disc", 60.0)
    finally:
        unregister("flat_disc")
    with pytest.raises((ParameterError, SceneError), match="face_radius_mm|flat_disc"):
        parse_scene(_scene("flat_disc"), "t")
    assert parse_scene(_scene("roller"), "t").cams[0].params.follower.kind == "roller"


def test_a_motion_replaced_under_its_name_is_the_one_composed():
    """A motion registered, removed, then registered again as another object under the same name: get_kind
    composes each from the entry registered at that time (its summary), and refuses it once removed."""
    from camgen.kinds import get_kind
    from camgen.motions import Motion, get_motion, register, unregister

    law = get_motion("motion_law")
    register(Motion("toy_law", "first summary", law.keys, read_law=law.read_law))
    try:
        assert get_kind("toy_law").summary == "first summary"
    finally:
        unregister("toy_law")
    with pytest.raises(KeyError):
        get_kind("toy_law")
    register(Motion("toy_law", "second summary", law.keys, read_law=law.read_law))
    try:
        assert get_kind("toy_law").summary == "second summary"
    finally:
        unregister("toy_law")
