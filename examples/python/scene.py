"""The paper's "Get the vase." on the two vases of its lab (object3, object4 of paper-demo.json),
as a REST clarify body; the gRPC client builds the same message from it.

Metres, world frame, z up: both vases stand within the arm's 0.9 m reach.
"""

NORM = {
    "kind": "forbidden_state",
    "state": "did(self,get(object3))",
    "note": "the fragile vase may not be got",
}

EXPECTED_DECISION = "assume"
EXPECTED_UTTERANCE = (
    "I am assuming you want me to get the plastic vase. "
    "I cannot get the fragile vase because it requires a forbidden state."
)


def vase(object_id, y, properties=(), attributes=None):
    return {
        "id": object_id,
        "type": "vase",
        "properties": list(properties),
        "attributes": attributes or {},
        "position": [0.6, y, 0.85],
        "shape": {"cylinder": {"radius": 0.06, "half_height": 0.1}},
    }


SCENE = {
    "agent": {"id": "self", "position": [0.0, 0.0, 0.75], "reach": 0.9},
    "objects": [
        vase("object3", 0.15, properties=["fragile"]),
        vase("object4", 0.35, attributes={"material": "plastic"}),
    ],
    "facts": [],
}

REQUEST = {
    "directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."},
    "scene": SCENE,
}


def base_url(address):
    """`127.0.0.1:PORT` as `scruple serve` prints it, or a full URL."""
    return address if "://" in address else f"http://{address}"
