"""The models on their own: what a request puts on the wire, and what an answer tolerates.
No server is needed."""

from __future__ import annotations

import json

import pytest
from pydantic import ValidationError

from scruple_client import (
    AnswerBody,
    ClarifyBody,
    DecisionDto,
    DirectiveBody,
    NormBody,
    NormDto,
    ObjectBody,
    OptionsBody,
    ReferenceBody,
    SceneBody,
    ShapeBody,
)

from scenes import LAB

# The README's answer to "Get the vase.", with two members no version of the API has.
README_ANSWER = {
    "decision": "assume",
    "utterance": "I am assuming you want me to get the plastic vase. "
    "I cannot get the fragile vase because it requires a forbidden state.",
    "speech_act": "assume(self,mean(human,did(self,get(object4))))",
    "goal": "did(self,get(object4))",
    "interpretations": [
        {"action": "did(self,get(object3))", "description": "the fragile vase", "permissible": False, "feasible": True,
         "reasons": [{"kind": "forbidden_state", "detail": "did(self,get(object3))", "norm_id": 2, "severity": 3,
                      "words": "it requires a forbidden state", "since": "2027"}],
         "plan": ["get(object3)"], "score": 1.0},
        {"action": "did(self,get(object4))", "description": "the plastic vase", "permissible": True, "feasible": True,
         "reasons": [], "plan": ["get(object4)"], "score": 1.0},
    ],
    "offered": ["did(self,get(object4))"],
    "norm_version": 2,
    "library_version": 1,
    "text": "Get the vase.",
    "confidence": 0.9,
}


def test_a_request_sends_only_what_was_set() -> None:
    request = ClarifyBody(
        directive=DirectiveBody(action="get", arguments=[ReferenceBody(type="vase")]),
        scene=SceneBody.model_validate(LAB),
    )
    wire = request.wire()
    assert wire["directive"] == {"action": "get", "arguments": [{"type": "vase"}]}
    assert set(wire) == {"directive", "scene"}
    assert "null" not in json.dumps(wire)


def test_explicit_options_are_sent_and_unset_ones_are_not() -> None:
    request = ClarifyBody(
        directive=DirectiveBody(text="Get the vase."),
        scene=SceneBody.model_validate(LAB),
        options=OptionsBody(single_permissible="confirm"),
        answer=AnswerBody(choice=0),
        focus=["object4"],
    )
    wire = request.wire()
    assert wire["options"] == {"single_permissible": "confirm"}
    assert wire["answer"] == {"choice": 0}
    assert wire["focus"] == ["object4"]


def test_attribute_values_keep_their_json_type() -> None:
    thing = ObjectBody(id="o1", type="box", position=[0, 0, 0], attributes={"n": 3, "ok": True, "w": 1.5, "c": "red"})
    assert thing.wire()["attributes"] == {"n": 3, "ok": True, "w": 1.5, "c": "red"}
    assert json.dumps(thing.wire()["attributes"]) == '{"n": 3, "ok": true, "w": 1.5, "c": "red"}'


def test_scenes_keep_the_members_perception_attaches() -> None:
    scene = SceneBody.model_validate(
        {"agent": {"position": [0, 0, 0.75], "reach": 0.9, "frame": "base_link"},
         "objects": [{"id": "cup1", "type": "cup", "position": [0.5, 0, 0.8], "tracker_id": 17}],
         "stamp": 12.5}
    )
    wire = scene.wire()
    assert wire["stamp"] == 12.5
    assert wire["agent"]["frame"] == "base_link"
    assert wire["objects"][0]["tracker_id"] == 17


def test_a_misspelt_option_fails_before_it_is_sent() -> None:
    with pytest.raises(ValidationError, match="strategie"):
        OptionsBody.model_validate({"strategie": "reflexive"})
    with pytest.raises(ValidationError):
        OptionsBody(strategy="cautious")  # type: ignore[arg-type]


def test_an_answer_is_exactly_one_thing() -> None:
    with pytest.raises(ValidationError, match="exactly one"):
        AnswerBody()
    with pytest.raises(ValidationError, match="exactly one"):
        AnswerBody(text="the red one", choice=1)
    assert AnswerBody(choice="alternative").wire() == {"choice": "alternative"}


def test_a_shape_is_exactly_one_kind() -> None:
    assert ShapeBody.model_validate({"ball": {"radius": 0.1}}).wire() == {"ball": {"radius": 0.1}}
    with pytest.raises(ValidationError, match="exactly one"):
        ShapeBody.model_validate({})


def test_an_answer_with_members_this_client_does_not_know_still_parses() -> None:
    decision = DecisionDto.model_validate(README_ANSWER)
    assert decision.decision == "assume"
    assert decision.goal == "did(self,get(object4))"
    assert decision.interpretations[0].reasons[0].norm_id == 2
    assert decision.model_extra == {"confidence": 0.9}
    assert decision.interpretations[0].reasons[0].model_extra == {"since": "2027"}
    assert decision.interpretations[1].norm_score == 0
    assert not decision.asks


def test_a_decision_the_client_does_not_know_still_parses() -> None:
    decision = DecisionDto.model_validate({**README_ANSWER, "decision": "defer", "goal": None})
    assert decision.decision == "defer"


def test_a_stored_norm_goes_back_as_a_body() -> None:
    stored = NormDto.model_validate(
        {"id": 2, "revision": 5, "kind": "forbidden_state", "state": "did(self,get(object3))", "when": [],
         "severity": 3, "note": "the fragile vase may not be got", "added_by": "a newer service"}
    )
    body = stored.to_body()
    assert isinstance(body, NormBody)
    assert body.wire() == {"id": 2, "kind": "forbidden_state", "state": "did(self,get(object3))", "when": [],
                           "severity": 3, "note": "the fragile vase may not be got", "roles": [], "exempt_roles": []}
    assert "id" not in stored.to_body(keep_id=False).wire()
