"""Scenes and expected words the tests share (metres, world frame, z up)."""

from __future__ import annotations

from typing import Any


def _cylinder(radius: float, half_height: float) -> dict[str, Any]:
    return {"cylinder": {"radius": radius, "half_height": half_height}}


#: The paper's lab (``../shared/scenarios/paper-demo.json``, ``scenes.lab``): two notebooks,
#: the fragile vase ``object3`` and the plastic vase ``object4``, and a mug, all within reach.
LAB: dict[str, Any] = {
    "agent": {"id": "self", "position": [0, 0, 0.75], "reach": 0.9},
    "objects": [
        {"id": "object1", "type": "notebook", "attributes": {"color": "red"}, "position": [0.55, -0.4, 0.76],
         "shape": {"cuboid": {"half_extents": [0.105, 0.148, 0.01]}}},
        {"id": "object2", "type": "notebook", "attributes": {"color": "green"}, "position": [0.55, -0.08, 0.76],
         "shape": {"cuboid": {"half_extents": [0.105, 0.148, 0.01]}}},
        {"id": "object3", "type": "vase", "properties": ["fragile"], "position": [0.6, 0.15, 0.85],
         "shape": _cylinder(0.06, 0.1)},
        {"id": "object4", "type": "vase", "attributes": {"material": "plastic"}, "position": [0.6, 0.35, 0.85],
         "shape": _cylinder(0.06, 0.1)},
        {"id": "object5", "type": "mug", "position": [0.5, 0.5, 0.8], "shape": _cylinder(0.04, 0.05)},
    ],
}

#: The README's kitchen: a red and a blue mug, a sink and a fragile vase.
KITCHEN: dict[str, Any] = {
    "agent": {"position": [0, 0, 0.75], "reach": 0.9},
    "objects": [
        {"id": "mug1", "type": "mug", "attributes": {"color": "red"}, "position": [0.5, 0.1, 0.8]},
        {"id": "mug2", "type": "mug", "attributes": {"color": "blue"}, "position": [0.5, 0.3, 0.8]},
        {"id": "sink1", "type": "sink", "position": [0.6, -0.2, 0.8]},
        {"id": "vase1", "type": "vase", "properties": ["fragile"], "position": [0.6, 0.4, 0.85]},
    ],
}

#: The paper's answer to "Get the vase." in the lab under its norms.
VASE_ASSUMED = (
    "I am assuming you want me to get the plastic vase. "
    "I cannot get the fragile vase because it requires a forbidden state."
)
#: The question "Get the mug." asks in the kitchen.
WHICH_MUG = "Do you mean that you want me to get the blue mug or that you want me to get the red mug?"
