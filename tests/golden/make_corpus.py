#!/usr/bin/env python3
"""Writes tests/golden/corpus.jsonl: the requests whose answers must not change while the code is
reshaped (tests/api/golden.rs answers each on a fresh store and compares with the golden files).

The corpus: the paper's cases under every strategy, style and single-permissible option; the
README's examples; generated scenes that reach every decision kind and every reason kind the
service can give deterministically; directives and answers in words; soft norms; and requests
that end in every error it answers. Each entry is {"id", "setup": [REQUEST...], "request":
REQUEST, "replay": bool}, a REQUEST being {"method", "path", "body"} (JSON) or {"method", "path",
"raw", "headers"}. Entries marked replay are also decided by `scruple replay --out` with the
setup's norms as its --norms file; entries marked grpc (a clarify or a norm's creation) are also
sent over gRPC, after the same setup over REST, and their answers kept in grpc.jsonl.
Run from the checkout: python3 tests/golden/make_corpus.py [path/to/paper-demo.json]
"""
import copy
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
demo = json.load(open(sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "../../../shared/scenarios/paper-demo.json")))
lab, office = demo["scenes"]["lab"], demo["scenes"]["office"]
entries = []


def post(path, body):
    return {"method": "POST", "path": path, "body": body}


def norms_setup(norms):
    return [post("/v1/norms", n) for n in norms]


def add(id, request, setup=(), replay=False, server=None, grpc=False):
    entry = {"id": id, "setup": list(setup), "request": request, "replay": replay}
    if server:
        entry["server"] = server
    if grpc:
        entry["grpc"] = True
    entries.append(entry)


def clarify(id, body, norms=(), replay=True, setup=(), grpc=False):
    add(id, post("/v1/clarify", body), list(setup) + norms_setup(norms), replay and not setup, grpc=grpc)


# The paper's cases, under every option that changes words or decisions.
for i, case in enumerate(demo["cases"]):
    base = {"directive": dict(case["directive"], text=case["text"]), "scene": demo["scenes"][case["scene"]]}
    if "options" in case:
        base["options"] = case["options"]
    for strategy in ["moral", "reflexive"]:
        for style in ["diarc", "natural"]:
            for single in ["assume", "confirm"]:
                body = copy.deepcopy(base)
                body["options"] = dict(body.get("options", {}), strategy=strategy, style=style, single_permissible=single)
                clarify(f"paper-{i}-{strategy}-{style}-{single}", body, demo["norms"],
                        grpc=strategy == "moral" and single == "assume")
    clarify(f"paper-{i}-no-norms", base)

# The README's examples.
clarify("readme-confirm-above-ratio", {"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": lab,
                                       "options": {"confirm_above_ratio": 0.4}}, demo["norms"])
clarify("readme-answer-reference", {"directive": {"action": "get", "arguments": [{"type": "notebook"}]}, "scene": lab,
                                    "answer": {"reference": {"attributes": {"color": "red"}}}})
clarify("readme-natural-grouped", {"directive": {"action": "destroy", "arguments": [{"type": "notebook"}]}, "scene": lab,
                                   "options": {"style": "natural"}}, demo["norms"])
owner_norm = {"kind": "forbidden_action", "action": "steal", "exempt_roles": ["owner"],
              "note": "only the owner may have the cash box taken"}
for roles in [["owner"], [], ["visitor"]]:
    clarify(f"readme-roles-{'-'.join(roles) or 'none'}", {"speaker_roles": roles, "directive": {"action": "steal", "arguments": [{"type": "cash_box"}]},
                                                      "scene": office}, [owner_norm])
add("readme-check", post("/v1/check", {"scene": lab, "steps": ["get(object4)", "get(object3)"]}), norms_setup(demo["norms"]))
add("readme-bad-norm", post("/v1/norms", {"kind": "forbidden_action", "action": "get(X", "severity": 3}))
add("readme-open-verb", post("/v1/clarify", {"directive": {"action": "open", "arguments": [{"type": "box"}]},
                                             "scene": {"agent": {"position": [0, 0, 0.75], "reach": 0.9},
                                                       "objects": [{"id": "box1", "type": "box", "position": [0.5, 0, 0.8]}]}}),
    [{"method": "PUT", "path": "/v1/actions/open", "body": {"parameters": ["X"], "methods": [
        {"reach": ["X"], "preconditions": ["closed(X)"], "adds": ["open(X)"], "removes": ["closed(X)"]}]}}])

# Generated scenes: every decision kind and reason kind, in both styles.
def thing(id, kind, x, y, z=0.8, **extra):
    return dict({"id": id, "type": kind, "position": [x, y, z]}, **extra)


agent = {"position": [0, 0, 0.75], "reach": 0.9}
kitchen = {"agent": dict(agent, gripper_aperture=0.12, payload=1.0, gripper_size=0.03), "objects": [
    thing("cup1", "cup", 0.4, 0.1, attributes={"color": "red"}, shape={"cylinder": {"radius": 0.04, "half_height": 0.05}}),
    thing("cup2", "cup", 0.4, -0.1, attributes={"color": "blue"}, shape={"cylinder": {"radius": 0.04, "half_height": 0.05}}),
    thing("cup3", "cup", 2.0, 0.0, attributes={"color": "green"}),
    thing("pot", "pot", 0.5, 0.3, shape={"cylinder": {"radius": 0.2, "half_height": 0.1}}),
    thing("anvil", "anvil", 0.3, -0.3, mass=20, shape={"cuboid": {"half_extents": [0.05, 0.05, 0.05]}}),
    thing("plate", "plate", 0.5, 0.0, 0.76, shape={"cylinder": {"radius": 0.1, "half_height": 0.01}}),
    thing("saucer", "plate", 0.6, -0.2, 0.76, shape={"cylinder": {"radius": 0.02, "half_height": 0.01}}),
    thing("box1", "box", 0.45, 0.25, properties=["closed"]),
], "facts": ["closed(box1)"]}
hard_norms = [
    {"kind": "forbidden_action", "action": "destroy", "severity": 5},
    {"kind": "forbidden_state", "state": "holding(self,X)", "when": ["red(X)"], "severity": 1},
    {"kind": "forbidden_action", "action": "put(X,Y)", "when": ["plate(Y)"], "context": "tidy", "severity": 2},
    {"kind": "forbidden_state", "state": "on(X,Y)", "roles": ["child"], "severity": 4},
]
for style in ["diarc", "natural"]:
    for verb, args in [("get", ["cup"]), ("get", ["pot"]), ("get", ["anvil"]), ("destroy", ["cup"]), ("get", ["spoon"]),
                       ("juggle", ["cup"]), ("put", ["cup", "plate"]), ("put", ["cup", "cup"]), ("pointTo", ["cup"]),
                       ("steal", ["box"]), ("get", ["plate"])]:
        for context in ["default", "tidy"]:
            body = {"directive": {"action": verb, "arguments": [{"type": a} for a in args]}, "scene": kitchen,
                    "context": context, "options": {"style": style}}
            clarify(f"kitchen-{verb}-{'-'.join(args)}-{context}-{style}", body, hard_norms)
    for attrs in [{"color": "red"}, {"color": "blue"}, {"color": "green"}, {"color": "purple"}]:
        body = {"directive": {"action": "get", "arguments": [{"type": "cup", "attributes": attrs}]}, "scene": kitchen,
                "options": {"style": style}}
        clarify(f"kitchen-get-{attrs['color']}-cup-{style}", body, hard_norms)
    child = {"speaker": "kid", "speaker_roles": ["child"], "directive": {"action": "put", "arguments": [{"type": "cup"}, {"type": "plate"}]},
             "scene": kitchen, "options": {"style": style}}
    clarify(f"kitchen-child-put-{style}", child, hard_norms)
    form = {"directive": {"form": "want(alice,did(self,get(X)))", "bindings": {"X": [{"id": "cup1", "score": 0.9}, {"id": "cup2", "score": 0.4}, "pot"]}},
            "scene": kitchen, "options": {"style": style}}
    clarify(f"kitchen-form-scored-{style}", form, hard_norms)
    unknown = {"directive": {"form": "did(self,get(X))", "bindings": {"X": ["cup1"]}}, "scene": kitchen, "options": {"style": style}}
    clarify(f"kitchen-form-{style}", unknown, hard_norms)
    thing_far = {"directive": {"form": "did(self,get(ghost))", "bindings": {}}, "scene": kitchen, "options": {"style": style}}
    clarify(f"kitchen-unknown-object-{style}", thing_far, hard_norms)
    open_box = {"directive": {"action": "open", "arguments": [{"type": "box"}]}, "scene": kitchen, "options": {"style": style}}
    add(f"kitchen-open-precondition-{style}", post("/v1/clarify", dict(open_box, scene=dict(kitchen, facts=[]))),
        [{"method": "PUT", "path": "/v1/actions/open", "body": {"parameters": ["X"], "methods": [
            {"reach": ["X"], "preconditions": ["closed(X)"], "adds": ["open(X)"], "removes": ["closed(X)"]}]}}])
    # Blocked: a wall between the arm and the cup, with clearance checked.
    blocked = {"agent": dict(agent, gripper_size=0.05), "objects": [
        thing("mug1", "mug", 0.6, 0.0), thing("wall", "wall", 0.3, 0.0, 0.75, shape={"cuboid": {"half_extents": [0.02, 0.3, 0.3]}})]}
    clarify(f"blocked-{style}", {"directive": {"action": "get", "arguments": [{"type": "mug"}]}, "scene": blocked, "options": {"style": style}})
    # Too deep: nine verbs, each the step of the one above.
    chain = [{"method": "PUT", "path": f"/v1/actions/deep{i}", "body": {"parameters": ["X"], "methods": [
        {"steps": [f"deep{i - 1}(X)"] if i > 0 else ["get(X)"]}]}} for i in range(10)]
    add(f"plan-too-deep-{style}", post("/v1/clarify", {"directive": {"action": "deep9", "arguments": [{"type": "cup"}]},
                                                       "scene": kitchen, "options": {"style": style}}), chain)
    for choice in [0, 1, 5]:
        body = {"directive": {"action": "get", "arguments": [{"type": "cup"}]}, "scene": kitchen, "answer": {"choice": choice},
                "options": {"style": style}}
        clarify(f"kitchen-answer-choice-{choice}-{style}", body)
    for limits in [{"max_readings": 1}, {"max_spoken": 2}, {"max_readings": 100000, "max_spoken": 2}]:
        many = {"agent": agent, "objects": [thing(f"c{i}", "cup", 0.4, -0.3 + 0.1 * i) for i in range(7)] +
                [thing(f"p{i}", "plate", 0.5, -0.3 + 0.1 * i, 0.76) for i in range(3)]}
        body = {"directive": {"action": "put", "arguments": [{"type": "cup"}, {"type": "plate"}]}, "scene": many,
                "options": dict(limits, style=style)}
        clarify(f"many-{'-'.join(f'{k}{v}' for k, v in limits.items())}-{style}", body)
    clarify(f"empty-scene-{style}", {"directive": {"action": "get", "arguments": [{"type": "cup"}]},
                                     "scene": {"agent": agent}, "options": {"style": style}})
    clarify(f"confirm-ratio-{style}", {"directive": {"action": "get", "arguments": [{"type": "cup"}]}, "scene": kitchen,
                                       "options": {"style": style, "confirm_above_ratio": 0.1}}, hard_norms)
    add(f"check-kitchen-{style}", post("/v1/check", {"scene": kitchen, "steps": ["get(cup2)", "put(cup2,plate)", "destroy(cup1)"],
                                                     "context": "tidy", "options": {"style": style}}), norms_setup(hard_norms))
    add(f"check-okay-{style}", post("/v1/check", {"scene": kitchen, "steps": ["pointTo(cup3)"], "options": {"style": style}}))

# Directives in words: the words a human says on the paper's lab, read as the structured
# directive they convey (or not understood), under the paper's norms. The words path is still
# growing, so several of these answers will change on purpose: re-bless in a commit that says why.
words = [
    ("simple-command", "Get the vase.", {}),
    ("simple-command-plastic", "Get the plastic vase.", {}),
    ("indirect-request", "Can you get the mug?", {}),
    ("indirect-polite", "Could you please destroy the red notebook?", {}),
    ("two-arguments", "Robot, would you mind putting the mug onto the green notebook now?", {}),
    ("vocative-first", "Pepper, get the vase.", {}),
    ("vocative-last", "Get the vase, Pepper.", {}),
    ("pronoun-focus", "Can you get it?", {"focus": ["object4", "object3"]}),
    ("pronoun-no-focus", "Can you get it?", {}),
    ("unknown-word", "Get the wet mug.", {}),
    ("no-such-object", "Get the spoon.", {}),
    ("question", "Is the vase fragile?", {}),
    ("negated", "Don't get the vase.", {}),
    ("word-salad", "Vase the notebook blue.", {}),
]
for name, text, extra in words:
    for style in ["diarc", "natural"]:
        body = dict({"directive": {"text": text}, "scene": lab, "options": {"style": style}}, **extra)
        clarify(f"words-{name}-{style}", body, demo["norms"], grpc=style == "diarc")
# Answers in words to the question the notebooks raise.
notebooks = {"directive": {"text": "Get the notebook."}, "scene": lab}
for name, answer in [("red-one", "the red one"), ("second-one", "the second one"), ("by-id", "object2"),
                     ("new-directive", "Get the vase."), ("never-mind", "never mind")]:
    clarify(f"words-answer-{name}", dict(notebooks, answer={"text": answer}), demo["norms"], grpc=name == "red-one")
clarify("words-answer-yes-after-confirm", {"directive": {"text": "Get the vase."}, "scene": lab,
                                           "options": {"single_permissible": "confirm"}, "answer": {"text": "yes"}},
        demo["norms"])
add("error-words-too-long", post("/v1/clarify", {"directive": {"text": "Get the vase " + "now " * 300}, "scene": lab}),
    grpc=True)

# Soft norms: "should" and "should not" rank the acceptable readings and never rescue a forbidden one.
def tray(dirty, clean):
    objects = [thing(f"mug{n + 1}", "mug", 0.5, 0.1 + 0.1 * n, properties=["clean"], attributes={"color": color})
               for n, color in enumerate(["blue", "red"][:clean])]
    if dirty:
        objects.append(thing("mug9", "mug", 0.5, -0.1, properties=["dirty"], attributes={"color": "green"}))
    return {"agent": {"id": "self", "position": [0, 0, 0.75], "reach": 0.9}, "objects": objects}


serving = {"kind": "discouraged_action", "action": "get(X)", "when": ["dirty(X)"], "context": "serving",
           "severity": 2, "note": "one serves with clean things"}
preferred = {"kind": "preferred_state", "state": "holding(self,X)", "when": ["blue(X)"], "severity": 1}
preferred_blue = dict(preferred, when=["color(X,blue)"])
forbidden_red = {"kind": "forbidden_action", "action": "get(X)", "when": ["color(X,red)"]}
for style in ["diarc", "natural"]:
    for name, scene, norms, extra in [
        ("dispreferred-dirty", tray(True, 1), [serving], {}),
        ("ask-among-clean", tray(True, 2), [serving], {}),
        ("only-dirty", tray(True, 0), [serving], {}),
        ("other-context", tray(True, 1), [serving], {"context": "default"}),
        ("ignored", tray(True, 1), [serving], {"options": {"soft_norms": "ignore"}}),
        ("reflexive", tray(True, 1), [serving], {"options": {"strategy": "reflexive"}}),
        ("preferred-blue", tray(False, 2), [preferred_blue], {"context": "default"}),
        ("never-rescues-forbidden", tray(False, 2), [forbidden_red, dict(preferred_blue, when=["color(X,red)"], severity=5)],
         {"context": "default"}),
        ("answer-choice", tray(True, 2), [serving], {"answer": {"choice": 1}}),
    ]:
        body = dict({"directive": {"text": "Hand me the mug."}, "scene": scene, "context": "serving"}, **extra)
        body["options"] = dict(body.get("options", {}), style=style)
        clarify(f"soft-{name}-{style}", body, norms, grpc=style == "diarc")
add("soft-norm-create", post("/v1/norms", serving), grpc=True)
add("soft-norm-list", {"method": "GET", "path": "/v1/norms"}, norms_setup([serving, preferred]))

# Norms and verbs: what writes answer.
add("norm-create", post("/v1/norms", {"kind": "forbidden_state", "state": "holding(self, X:object)", "when": ["fragile(X)"],
                                      "context": "lab", "severity": 4, "note": "n", "roles": ["child"], "exempt_roles": ["owner"]}),
    grpc=True)
add("norm-list", {"method": "GET", "path": "/v1/norms"}, norms_setup(hard_norms))
add("norm-get", {"method": "GET", "path": "/v1/norms/2"}, norms_setup(hard_norms))
add("norm-delete", {"method": "DELETE", "path": "/v1/norms/1"}, norms_setup(hard_norms))
add("norm-replace", {"method": "PUT", "path": "/v1/norms/1", "body": {"kind": "forbidden_action", "action": "steal"}}, norms_setup(hard_norms))
add("norm-replace-stale", {"method": "PUT", "path": "/v1/norms/1", "body": {"kind": "forbidden_action", "action": "steal"},
                           "headers": {"if-match": "\"99\""}}, norms_setup(hard_norms))
add("norm-set-export", {"method": "GET", "path": "/v1/norm-set"}, norms_setup(hard_norms))
add("norm-set-import", {"method": "PUT", "path": "/v1/norm-set", "body": {"norms": [{"id": 7, "kind": "forbidden_action", "action": "destroy"},
                                                                                 {"kind": "forbidden_action", "action": "steal"}]}})
add("norm-set-import-empty", {"method": "PUT", "path": "/v1/norm-set", "body": {"norms": []}}, norms_setup(hard_norms))
add("actions-list", {"method": "GET", "path": "/v1/actions"})
add("action-get", {"method": "GET", "path": "/v1/actions/put"})
add("action-put", {"method": "PUT", "path": "/v1/actions/stack", "body": {"parameters": ["X", "Y"], "joiner": "on", "distinct": True,
                                                                         "methods": [{"steps": ["get(X)", "itself"], "reach": ["X", "Y"], "adds": ["on(X,Y)"]}]}})
add("action-delete", {"method": "DELETE", "path": "/v1/actions/steal"})
add("healthz", {"method": "GET", "path": "/healthz"})

# Every error the service answers.
bad_clarify = [
    ("no-directive", {"scene": lab}),
    ("no-scene", {"directive": {"action": "get", "arguments": [{"type": "mug"}]}}),
    ("unknown-member", {"directive": {"action": "get", "arguments": []}, "scene": lab, "colour": 1}),
    ("both-action-form", {"directive": {"action": "get", "form": "get(X)"}, "scene": lab}),
    ("neither", {"directive": {}, "scene": lab}),
    ("bad-form", {"directive": {"form": "get(X"}, "scene": lab}),
    ("unbound-variable", {"directive": {"form": "did(self,get(X))"}, "scene": lab}),
    ("unknown-binding", {"directive": {"form": "did(self,get(X))", "bindings": {"X": ["object3"], "Y": ["object4"]}}, "scene": lab}),
    ("binding-not-in-scene", {"directive": {"form": "did(self,get(X))", "bindings": {"X": ["object9"]}}, "scene": lab}),
    ("binding-twice", {"directive": {"form": "did(self,get(X))", "bindings": {"X": ["object3", "object3"]}}, "scene": lab}),
    ("bad-score", {"directive": {"form": "did(self,get(X))", "bindings": {"X": [{"id": "object3", "score": -1}]}}, "scene": lab}),
    ("id-not-in-scene", {"directive": {"action": "get", "arguments": [{"id": "object9"}]}, "scene": lab}),
    ("id-and-type", {"directive": {"action": "get", "arguments": [{"id": "object3", "type": "vase"}]}, "scene": lab}),
    ("empty-reference", {"directive": {"action": "get", "arguments": [{}]}, "scene": lab}),
    ("bad-verb", {"directive": {"action": "Get", "arguments": []}, "scene": lab}),
    ("bad-speaker", {"speaker": "Bob Smith", "directive": {"action": "get", "arguments": []}, "scene": lab}),
    ("bad-context", {"context": "", "directive": {"action": "get", "arguments": []}, "scene": lab}),
    ("bad-role", {"speaker_roles": ["a/b"], "directive": {"action": "get", "arguments": []}, "scene": lab}),
    ("bad-strategy", {"directive": {"action": "get", "arguments": []}, "scene": lab, "options": {"strategy": "greedy"}}),
    ("bad-max-spoken", {"directive": {"action": "get", "arguments": []}, "scene": lab, "options": {"max_spoken": 1}}),
    ("bad-deadline", {"directive": {"action": "get", "arguments": []}, "scene": lab, "options": {"deadline_ms": 0}}),
    ("bad-ratio", {"directive": {"action": "get", "arguments": []}, "scene": lab, "options": {"confirm_above_ratio": 1}}),
    ("bad-answer", {"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": lab, "answer": {}}),
    ("bad-choice", {"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": lab, "answer": {"choice": 9}}),
    ("nothing-asked", {"directive": {"action": "get", "arguments": [{"type": "mug"}]}, "scene": lab, "answer": {"choice": 0}}),
    ("no-agent", {"directive": {"action": "get", "arguments": []}, "scene": {}}),
    ("bad-reach", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": {"position": [0, 0, 0], "reach": -1}}}),
    ("bad-position", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": {"position": [0, 0], "reach": 1}}}),
    ("duplicate-object", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": agent, "objects": [thing("a", "cup", 0, 0), thing("a", "cup", 0, 0)]}}),
    ("bad-object-id", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": agent, "objects": [thing("A b", "cup", 0, 0)]}}),
    ("bad-radius", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": agent, "objects": [thing("a", "cup", 0, 0, shape={"ball": {"radius": 0}})]}}),
    ("bad-rotation", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": agent, "objects": [thing("a", "cup", 0, 0, rotation=[0, 0, 0, 2])]}}),
    ("bad-mass", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": agent, "objects": [thing("a", "cup", 0, 0, mass=-1)]}}),
    ("bad-fact", {"directive": {"action": "get", "arguments": []}, "scene": {"agent": agent, "facts": ["on(X,table)"]}}),
    ("wrong-type", {"directive": {"action": "get", "arguments": "vase"}, "scene": lab}),
]
for name, body in bad_clarify:
    add(f"error-clarify-{name}", post("/v1/clarify", body), grpc=name in ["id-not-in-scene", "bad-verb", "bad-strategy"])
bad_norms = [
    ("no-kind", {"action": "destroy"}),
    ("unknown-kind", {"kind": "forbidden_thought", "action": "destroy"}),
    ("no-action", {"kind": "forbidden_action"}),
    ("state-on-action", {"kind": "forbidden_action", "action": "destroy", "state": "on(X,Y)"}),
    ("variable-action", {"kind": "forbidden_action", "action": "X"}),
    ("bad-when", {"kind": "forbidden_action", "action": "destroy", "when": ["fragile("]}),
    ("bad-severity", {"kind": "forbidden_action", "action": "destroy", "severity": 6}),
    ("bad-context", {"kind": "forbidden_action", "action": "destroy", "context": ""}),
    ("role-both", {"kind": "forbidden_action", "action": "destroy", "roles": ["a"], "exempt_roles": ["a"]}),
    ("id-on-create", {"id": 3, "kind": "forbidden_action", "action": "destroy"}),
    ("unknown-member", {"kind": "forbidden_action", "action": "destroy", "whenever": []}),
]
for name, body in bad_norms:
    add(f"error-norm-{name}", post("/v1/norms", body), grpc=name in ["unknown-kind", "bad-severity", "bad-when"])
add("error-import-duplicate-id", {"method": "PUT", "path": "/v1/norm-set", "body": {"norms": [
    {"id": 2, "kind": "forbidden_action", "action": "a"}, {"id": 2, "kind": "forbidden_action", "action": "b"}]}})
add("error-import-no-norms", {"method": "PUT", "path": "/v1/norm-set", "body": {}})
add("error-import-bad-norm", {"method": "PUT", "path": "/v1/norm-set", "body": {"norms": [{"kind": "forbidden_action", "action": "a"}, {"kind": "x"}]}})
bad_verbs = [
    ("loop", "fetch", {"parameters": ["X"], "methods": [{"steps": ["fetch2(X)"]}]}),
    ("self-step", "open", {"parameters": ["X"], "methods": [{"steps": ["open(X)"]}]}),
    ("bad-parameter", "open", {"parameters": ["x"], "methods": [{}]}),
    ("no-methods", "open", {"parameters": ["X"], "methods": []}),
    ("unknown-variable", "open", {"parameters": ["X"], "methods": [{"adds": ["open(Y)"]}]}),
    ("name-differs", "open", {"name": "shut", "parameters": ["X"], "methods": [{}]}),
    ("bad-joiner", "open", {"parameters": ["X"], "joiner": "ON!", "methods": [{}]}),
]
# fetch2 calls fetch: storing fetch over fetch2 would loop.
loop_setup = [{"method": "PUT", "path": "/v1/actions/fetch2", "body": {"parameters": ["X"], "methods": [{"steps": ["fetch(X)"]}]}}]
for name, verb, body in bad_verbs:
    add(f"error-verb-{name}", {"method": "PUT", "path": f"/v1/actions/{verb}", "body": body}, loop_setup if name == "loop" else [])
add("error-not-found-norm", {"method": "GET", "path": "/v1/norms/99"})
add("error-not-found-norm-text", {"method": "GET", "path": "/v1/norms/abc"})
add("error-not-found-delete", {"method": "DELETE", "path": "/v1/norms/99"})
add("error-not-found-verb", {"method": "GET", "path": "/v1/actions/juggle"})
add("error-no-route", {"method": "GET", "path": "/v2/nowhere"})
add("error-method-not-allowed", {"method": "PATCH", "path": "/v1/norms"})
add("error-malformed", {"method": "POST", "path": "/v1/clarify", "raw": "{\"directive\": ", "headers": {"content-type": "application/json"}})
add("error-trailing", {"method": "POST", "path": "/v1/clarify", "raw": "{} x", "headers": {"content-type": "application/json"}})
add("error-media-type", {"method": "POST", "path": "/v1/clarify", "raw": "directive=get", "headers": {"content-type": "text/plain"}})
add("error-audit-limit", {"method": "GET", "path": "/v1/audit?limit=0"})
guarded = {"admin_token": "golden-admin-token", "max_body_bytes": 512}
add("error-unauthenticated", post("/v1/norms", {"kind": "forbidden_action", "action": "destroy"}), server=guarded)
add("error-forbidden", {"method": "POST", "path": "/v1/norms", "body": {"kind": "forbidden_action", "action": "destroy"},
                        "headers": {"authorization": "Bearer not-the-token"}}, server=guarded)
add("authorized-create", {"method": "POST", "path": "/v1/norms", "body": {"kind": "forbidden_action", "action": "destroy"},
                          "headers": {"authorization": "bearer golden-admin-token"}}, server=guarded)
add("error-payload-too-large", post("/v1/clarify", {"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": lab}),
    server=guarded)
add("error-check-no-steps", post("/v1/check", {"scene": lab, "steps": []}))
add("error-check-variable-step", post("/v1/check", {"scene": lab, "steps": ["get(X)"]}))

ids = [e["id"] for e in entries]
assert len(ids) == len(set(ids)), "ids are unique"
with open(os.path.join(here, "corpus.jsonl"), "w") as f:
    for e in entries:
        f.write(json.dumps(e, sort_keys=True, separators=(",", ":")) + "\n")
print(f"{len(entries)} entries, {sum(e['replay'] for e in entries)} also replayed")
