"""Write tokens against a server of the test's own, started with ``--admin-token``: writes need
the token (401 without, 403 with a wrong one), reads and decisions never do."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from scruple_client import AsyncClient, Client, Forbidden, Unauthorized

from scenes import LAB

TOKEN = "admin-token-for-the-python-tests-0123"
NORM = {"kind": "forbidden_state", "state": "did(self,get(object3))"}


@pytest.fixture
def guarded(start_server: Callable[..., str]) -> str:
    return start_server("--admin-token", TOKEN)


def test_a_write_without_the_token_is_unauthorized(guarded: str) -> None:
    with Client(guarded) as anonymous:
        with pytest.raises(Unauthorized) as raised:
            anonymous.create_norm(NORM)
        assert raised.value.status == 401
        assert raised.value.type == "/problems/unauthenticated"
        with pytest.raises(Unauthorized):
            anonymous.put_norm_set([NORM])
        with pytest.raises(Unauthorized):
            anonymous.delete_action("steal")
        assert anonymous.list_norms() == [], "nothing was written"


def test_a_wrong_token_is_forbidden(guarded: str) -> None:
    with Client(guarded, token="not-the-admin-token-at-all") as stranger:
        with pytest.raises(Forbidden) as raised:
            stranger.create_norm(NORM)
        assert raised.value.status == 403
        assert raised.value.type == "/problems/forbidden"


def test_the_token_lets_writes_through_and_decisions_need_none(guarded: str) -> None:
    with Client(guarded, token=TOKEN) as admin:
        created = admin.create_norm(NORM)
        replaced = admin.replace_norm(created.id, {**NORM, "severity": 5}, if_match=created.revision)
        assert replaced.severity == 5
        assert [n.id for n in admin.put_norm_set([replaced]).norms] == [created.id]
    with Client(guarded) as robot:
        assert [n.id for n in robot.list_norms()] == [created.id]
        decision = robot.clarify({"directive": {"text": "Get the vase."}, "scene": LAB})
        assert (decision.decision, decision.goal) == ("assume", "did(self,get(object4))")
        entries = robot.audit().entries
        assert [(e.actor, e.operation) for e in entries] == [
            ("admin", "create"), ("admin", "replace"), ("admin", "import")
        ]


@pytest.mark.anyio
@pytest.mark.parametrize("anyio_backend", ["asyncio"])
async def test_the_async_client_sends_the_token_too(guarded: str, anyio_backend: str) -> None:
    async with AsyncClient(guarded) as anonymous:
        with pytest.raises(Unauthorized):
            await anonymous.create_norm(NORM)
    async with AsyncClient(guarded, token=TOKEN) as admin:
        created = await admin.create_norm(NORM)
        await admin.delete_norm(created.id)
