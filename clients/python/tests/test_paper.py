"""The synchronous client against the live service: the paper's "Get the vase.", errors as a
user meets them, norms, verbs, checks and the audit trail."""

from __future__ import annotations

import pytest

from scruple_client import (
    Action,
    CheckBody,
    ClarifyBody,
    Client,
    DirectiveBody,
    InvalidField,
    Method,
    NormBody,
    NormDto,
    NotFound,
    OptionsBody,
    ReferenceBody,
    SceneBody,
    StaleRevision,
)

from scenes import LAB, VASE_ASSUMED


def test_get_the_vase_assumes_the_plastic_one(client: Client, paper_norms: list[NormDto]) -> None:
    fragile = next(n for n in paper_norms if n.state == "did(self,get(object3))")
    decision = client.clarify(
        ClarifyBody(
            directive=DirectiveBody(action="get", arguments=[ReferenceBody(type="vase")], text="Get the vase."),
            scene=SceneBody.model_validate(LAB),
        )
    )
    assert decision.decision == "assume"
    assert decision.utterance == VASE_ASSUMED
    assert decision.speech_act == "assume(self,mean(human,did(self,get(object4))))"
    assert decision.goal == "did(self,get(object4))"
    assert decision.offered == ["did(self,get(object4))"]
    assert decision.text == "Get the vase."
    glass, plastic = decision.interpretations
    assert (glass.description, glass.permissible, glass.feasible) == ("the fragile vase", False, True)
    assert [(r.kind, r.detail, r.norm_id) for r in glass.reasons] == [
        ("forbidden_state", "did(self,get(object3))", fragile.id)
    ]
    assert (plastic.description, plastic.permissible, plastic.feasible, plastic.reasons) == (
        "the plastic vase", True, True, []
    )


def test_the_same_in_the_humans_words(client: Client, paper_norms: list[NormDto]) -> None:
    decision = client.clarify({"directive": {"text": "Get the vase."}, "scene": LAB})
    assert (decision.decision, decision.utterance, decision.goal) == ("assume", VASE_ASSUMED, "did(self,get(object4))")
    assert decision.parse is not None
    assert decision.parse.form == "want(human,did(self,get(X)))"
    assert [(r.words, r.candidates) for r in decision.parse.references] == [("the vase", ["object3", "object4"])]


def test_confirm_instead_of_assuming(client: Client, paper_norms: list[NormDto]) -> None:
    decision = client.clarify(
        ClarifyBody(
            directive=DirectiveBody(text="Get the vase."),
            scene=SceneBody.model_validate(LAB),
            options=OptionsBody(single_permissible="confirm"),
        )
    )
    assert decision.decision == "confirm"
    assert decision.goal is None
    assert decision.utterance == (
        "Do you want me to get the plastic vase? I cannot get the fragile vase because it requires a forbidden state."
    )
    assert decision.asks


def test_a_bad_norm_raises_invalid_field_at_action(client: Client) -> None:
    before = client.get_norm_set().version
    with pytest.raises(InvalidField) as raised:
        client.create_norm(NormBody(kind="forbidden_action", action="get(X"))
    error = raised.value
    assert error.status == 422
    assert error.field == "/action"
    assert error.type == "/problems/invalid-field"
    assert error.title == "Invalid field"
    assert "not a term" in (error.detail or "")
    assert '"field":"/action"' in error.body
    assert client.get_norm_set().version == before, "nothing is stored"


def test_a_bad_directive_raises_invalid_field_naming_it(client: Client) -> None:
    with pytest.raises(InvalidField) as raised:
        client.clarify({"directive": {"action": "Get", "arguments": [{"type": "vase"}]}, "scene": LAB})
    assert raised.value.field == "/directive/action"
    with pytest.raises(InvalidField) as unknown:
        client.clarify({"directive": {"text": "Get it."}, "scene": LAB, "focus": ["object9"]})
    assert unknown.value.field == "/focus/0"


def test_an_unknown_norm_raises_not_found(client: Client) -> None:
    with pytest.raises(NotFound) as raised:
        client.get_norm(987654321)
    assert raised.value.status == 404


def test_norms_round_trip_with_revisions(client: Client) -> None:
    client.put_norm_set([])
    created = client.create_norm({"kind": "forbidden_state", "state": "did(self,get(object3))"})
    assert (created.kind, created.state, created.when, created.severity) == (
        "forbidden_state", "did(self,get(object3))", [], 3
    )
    assert client.get_norm(created.id) == created
    assert [n.id for n in client.list_norms()] == [created.id]

    stronger = created.model_copy(update={"severity": 5})
    replaced = client.replace_norm(created.id, stronger, if_match=created.revision)
    assert (replaced.id, replaced.severity) == (created.id, 5)
    assert replaced.revision > created.revision

    with pytest.raises(StaleRevision) as stale:
        client.replace_norm(created.id, {"kind": "forbidden_state", "state": "did(self,get(object4))"},
                            if_match=created.revision)
    assert stale.value.status == 412
    assert client.get_norm(created.id).state == "did(self,get(object3))", "a stale write changes nothing"

    client.delete_norm(created.id, if_match=replaced.revision)
    with pytest.raises(NotFound):
        client.get_norm(created.id)


def test_the_audit_trail_records_each_change(client: Client) -> None:
    start = client.audit(limit=1000)
    while len(start.entries) == 1000:
        start = client.audit(after=start.next_after, limit=1000)
    created = client.create_norm({"kind": "forbidden_action", "action": "juggle"})
    client.delete_norm(created.id)
    page = client.audit(after=start.next_after)
    assert [(e.subject, e.operation, e.target) for e in page.entries] == [
        ("norm", "create", str(created.id)),
        ("norm", "delete", str(created.id)),
    ]
    assert page.entries[0].after is not None and page.entries[0].after["action"] == "juggle"
    assert page.next_after == page.entries[-1].id


def test_check_refuses_the_forbidden_step(client: Client, paper_norms: list[NormDto]) -> None:
    refused = client.check(CheckBody(scene=SceneBody.model_validate(LAB), steps=["get(object3)"]))
    assert not refused.permitted
    assert refused.utterance == "I cannot get the fragile vase because it requires a forbidden state."
    assert [s.step for s in refused.steps] == ["get(object3)"]
    assert not refused.steps[0].permissible and refused.steps[0].feasible
    allowed = client.check({"scene": LAB, "steps": ["get(object4)"]})
    assert allowed.permitted and allowed.utterance == "Okay."


def test_verbs_can_be_read_added_and_removed(client: Client) -> None:
    names = {a.name for a in client.list_actions()}
    assert {"get", "put", "pointTo", "destroy", "steal"} <= names
    put = client.get_action("put")
    assert put.parameters == ["X", "Y"] and put.methods

    juggle = Action(
        parameters=["X"],
        words=["juggle"],
        methods=[Method(reach=["X"], adds=["juggled(X)"])],
    )
    stored = client.put_action("juggle", juggle)
    assert (stored.name, stored.parameters, stored.words) == ("juggle", ["X"], ["juggle"])
    decision = client.clarify({"directive": {"text": "Juggle the mug."}, "scene": LAB})
    assert (decision.decision, decision.goal) == ("comply", "did(self,juggle(object5))")

    client.delete_action("juggle")
    with pytest.raises(NotFound):
        client.get_action("juggle")
    gone = client.clarify({"directive": {"action": "juggle", "arguments": [{"id": "object5"}]}, "scene": LAB})
    assert gone.decision == "refuse"
    assert gone.utterance == "I cannot juggle the mug because I do not know how to juggle."


def test_healthz_is_ok(client: Client) -> None:
    assert client.healthz().status == "ok"
