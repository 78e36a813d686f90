"""``PUT /v1/norm-set``: ``replace`` makes the set exactly what is sent; ``merge`` keeps the
stored norms not named by id, replaces those named, and adds those without an id."""

from __future__ import annotations

import pytest

from scruple_client import Client, InvalidField, NormBody, StaleRevision

DESTROY = {"kind": "forbidden_action", "action": "destroy"}
STEAL = {"kind": "forbidden_action", "action": "steal"}
VASE = {"kind": "forbidden_state", "state": "did(self,get(object3))"}
JUGGLE = {"kind": "discouraged_action", "action": "juggle", "severity": 2}


def rules(client: Client) -> list[tuple[int, str]]:
    return [(n.id, n.action or n.state or "") for n in client.get_norm_set().norms]


def test_replace_makes_the_set_exactly_what_is_sent(client: Client) -> None:
    start = client.put_norm_set([DESTROY, STEAL])
    assert [n.action for n in start.norms] == ["destroy", "steal"]
    replaced = client.put_norm_set([VASE])
    assert [n.state for n in replaced.norms] == ["did(self,get(object3))"]
    assert replaced.version > start.version
    assert rules(client) == [(replaced.norms[0].id, "did(self,get(object3))")]


def test_replace_keeps_the_ids_it_is_given(client: Client) -> None:
    first = client.put_norm_set([DESTROY, STEAL]).norms
    restored = client.put_norm_set(first)  # stored norms go back with their ids
    assert [(n.id, n.action) for n in restored.norms] == [(n.id, n.action) for n in first]


def test_merge_keeps_what_it_does_not_name(client: Client) -> None:
    destroy, steal = client.put_norm_set([DESTROY, STEAL]).norms
    merged = client.put_norm_set([VASE], mode="merge")
    assert [(n.action or n.state) for n in merged.norms] == ["destroy", "steal", "did(self,get(object3))"]
    added = merged.norms[2]
    assert added.id not in (destroy.id, steal.id)
    assert (merged.norms[0].id, merged.norms[1].id) == (destroy.id, steal.id)
    assert merged.norms[0].revision == destroy.revision, "a norm not named is kept as it was"


def test_merge_replaces_the_norm_it_names_by_id(client: Client) -> None:
    destroy, steal = client.put_norm_set([DESTROY, STEAL]).norms
    softer = NormBody.model_validate({**JUGGLE, "id": steal.id})
    merged = client.put_norm_set([softer], mode="merge")
    assert [(n.id, n.kind, n.action) for n in merged.norms] == [
        (destroy.id, "forbidden_action", "destroy"),
        (steal.id, "discouraged_action", "juggle"),
    ]
    assert client.get_norm(steal.id).severity == 2


def test_merging_nothing_changes_nothing(client: Client) -> None:
    before = client.put_norm_set([DESTROY, STEAL])
    after = client.put_norm_set([], mode="merge")
    assert [(n.id, n.revision) for n in after.norms] == [(n.id, n.revision) for n in before.norms]


def test_replace_spelt_out_is_the_default(client: Client) -> None:
    client.put_norm_set([DESTROY, STEAL])
    answer = client.request("PUT", "/v1/norm-set", json={"norms": [VASE], "mode": "replace"})
    assert answer.status_code == 200
    assert [n[1] for n in rules(client)] == ["did(self,get(object3))"]


def test_any_other_mode_is_invalid_at_mode(client: Client) -> None:
    before = client.put_norm_set([DESTROY])
    with pytest.raises(InvalidField) as raised:
        client.request("PUT", "/v1/norm-set", json={"norms": [VASE], "mode": "overwrite"})
    assert (raised.value.status, raised.value.field) == (422, "/mode")
    assert client.get_norm_set().version == before.version, "nothing is written"


def test_a_bad_norm_in_the_set_names_it_and_writes_nothing(client: Client) -> None:
    before = client.put_norm_set([DESTROY])
    with pytest.raises(InvalidField) as raised:
        client.put_norm_set([STEAL, {"kind": "forbidden_action", "action": "steal", "severity": 9}])
    assert raised.value.field == "/norms/1/severity"
    assert client.get_norm_set() == before


def test_if_match_guards_the_whole_set(client: Client) -> None:
    read = client.put_norm_set([DESTROY])
    client.put_norm_set([STEAL], if_match=read.version)
    with pytest.raises(StaleRevision) as stale:
        client.put_norm_set([VASE], if_match=read.version)
    assert stale.value.status == 412
    assert [n[1] for n in rules(client)] == ["steal"]
