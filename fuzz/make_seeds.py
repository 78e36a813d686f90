#!/usr/bin/env python3
"""Writes the committed seed corpus for the fuzz targets from ../shared/scenarios/paper-demo.json.

Seeds are the paper's requests, built as tests/api/paper_demo.rs builds them, plus a few that
reach what the paper does not use (follow-up answers, scores, roles, shapes, limits).
Run from fuzz/: python3 make_seeds.py [path/to/paper-demo.json]
"""
import copy
import json
import os
import sys

demo = json.load(open(sys.argv[1] if len(sys.argv) > 1 else "../../shared/scenarios/paper-demo.json"))


def write(target, name, text):
    os.makedirs(f"seeds/{target}", exist_ok=True)
    with open(f"seeds/{target}/{name}", "w") as f:
        f.write(text)


bodies = []
for case in demo["cases"]:
    directive = dict(case["directive"], text=case["text"])
    body = {"directive": directive, "scene": demo["scenes"][case["scene"]]}
    if "options" in case:
        body["options"] = case["options"]
    bodies.append(body)

lab = demo["scenes"]["lab"]
ids = [o["id"] for o in lab["objects"]]
extra = [
    {"speaker": "human", "directive": {"form": "want(human,did(self,get(X)))",
                                       "bindings": {"X": [{"id": ids[0], "score": 0.7}, ids[-1]]}}, "scene": lab},
    {"directive": {"action": "put", "arguments": [{"type": "vase"}, {"id": ids[0]}]}, "scene": lab,
     "options": {"style": "natural", "max_spoken": 2, "max_readings": 3, "deadline_ms": 5,
                 "confirm_above_ratio": 0.5}},
    {"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": lab, "answer": {"choice": 0}},
    {"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": lab, "answer": {"id": ids[0]}},
    {"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": lab,
     "answer": {"reference": {"type": "vase", "attributes": {"material": "plastic"}, "properties": ["fragile"]}}},
    {"speaker": "alice", "speaker_roles": ["owner", "child"], "context": "hospital",
     "directive": {"action": "pointTo", "arguments": [{"type": "vase"}]}, "scene": lab},
    {"directive": {"form": "did(self,put(X,Y))", "bindings": {"X": ["a"], "Y": ["b"]}},
     "scene": {"agent": {"id": "self", "position": [0, 0, 0.75], "reach": 0.9, "gripper_aperture": 0.1,
                         "payload": 1.5, "gripper_size": 0.03},
               "objects": [{"id": "a", "type": "box", "position": [0.3, 0, 0.8], "mass": 2,
                            "shape": {"cuboid": {"half_extents": [0.1, 0.05, 0.05]}},
                            "rotation": [0, 0, 0.7071068, 0.7071068], "attributes": {"lid": True, "n": 3}},
                           {"id": "b", "type": "tray", "position": [0.5, 0.1, 0.8],
                            "shape": {"ball": {"radius": 0.05}}}],
               "facts": ["closed(a)", "on(a,b)"]}},
]
bodies.extend(extra)
for i, body in enumerate(bodies):
    write("clarify_request", f"request-{i:02}.json", json.dumps(body, separators=(",", ":")))

# Inputs that store verbs before clarifying (see fuzz_targets/clarify_request.rs): a chain of
# verbs whose every method fails, up to one the expansion bound refuses, and a distinct verb.
def over(callee):
    return {"parameters": ["X"], "methods": [{"steps": [f"{callee}(X)"] * 4}] * 8}


with_verbs = [
    {"verbs": {"a0": {"parameters": ["X"], "methods": [{"preconditions": ["never(X)"]}]},
               "a1": over("a0"), "a2": over("a1"), "a3": over("a2"),
               "pair": {"parameters": ["X", "Y"], "distinct": True, "joiner": "with",
                        "methods": [{"steps": ["a2(X)", "a2(Y)"]}, {"steps": ["get(X)", "itself"], "reach": ["X", "Y"]}]}},
     "request": {"directive": {"action": "pair", "arguments": [{"type": "vase"}, {"type": "notebook"}]}, "scene": lab,
                 "options": {"deadline_ms": 50}}},
    {"verbs": {"stack": {"parameters": ["X", "Y"], "distinct": True, "joiner": "on",
                         "methods": [{"steps": ["get(X)", "itself"], "reach": ["X", "Y"], "adds": ["on(X,Y)"]}]}},
     "request": {"directive": {"action": "stack", "arguments": [{"type": "vase"}, {"type": "vase"}]}, "scene": lab}},
]
for i, body in enumerate(with_verbs):
    write("clarify_request", f"verbs-{i:02}.json", json.dumps(body, separators=(",", ":")))

terms = ["did(self,get(object3))", "want(human, did(self, get(X)))", "holding(self,?x)", "on(X:object, table1:surface)",
         "f(g(h(a,B),-1.5),_c)", "pointTo(object4)"]
for i, term in enumerate(terms):
    write("term_parser", f"term-{i:02}.txt", term)
