"""The asynchronous client and conversation against the live service: the same answers as the
synchronous ones, and many decisions in flight at once."""

from __future__ import annotations

import os
from collections.abc import AsyncIterator

import anyio
import pytest

from scruple_client import AsyncClient, AsyncConversation, InvalidField, NotFound

from conftest import PAPER_NORMS
from scenes import KITCHEN, LAB, VASE_ASSUMED, WHICH_MUG

pytestmark = pytest.mark.anyio


@pytest.fixture
def anyio_backend() -> str:
    return "asyncio"


@pytest.fixture
async def aclient(server_url: str) -> AsyncIterator[AsyncClient]:
    async with AsyncClient(server_url, token=os.environ.get("SCRUPLE_TOKEN") or None) as c:
        await c.put_norm_set([])
        for norm in PAPER_NORMS:
            await c.create_norm(norm)
        yield c


async def test_get_the_vase_assumes_the_plastic_one(aclient: AsyncClient) -> None:
    decision = await aclient.clarify(
        {"directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."}, "scene": LAB}
    )
    assert (decision.decision, decision.utterance, decision.goal) == ("assume", VASE_ASSUMED, "did(self,get(object4))")


async def test_many_decisions_at_once_each_get_the_paper_s_answer(aclient: AsyncClient) -> None:
    answers: list[str] = []

    async def ask() -> None:
        answers.append((await aclient.clarify({"directive": {"text": "Get the vase."}, "scene": LAB})).utterance)

    async with anyio.create_task_group() as tg:
        for _ in range(16):
            tg.start_soon(ask)
    assert answers == [VASE_ASSUMED] * 16


async def test_errors_raise_as_in_the_sync_client(aclient: AsyncClient) -> None:
    with pytest.raises(InvalidField) as raised:
        await aclient.create_norm({"kind": "forbidden_action", "action": "get(X"})
    assert (raised.value.status, raised.value.field) == (422, "/action")
    with pytest.raises(NotFound):
        await aclient.get_norm(987654321)


async def test_norms_verbs_and_health(aclient: AsyncClient) -> None:
    norms = await aclient.list_norms()
    assert [n.action or n.state for n in norms] == ["destroy", "did(self,get(object3))", "steal"]
    norm_set = await aclient.get_norm_set()
    assert [n.id for n in norm_set.norms] == [n.id for n in norms]
    assert (await aclient.get_action("get")).parameters == ["X"]
    assert (await aclient.healthz()).status == "ok"
    page = await aclient.audit(limit=1)
    assert len(page.entries) == 1


async def test_a_conversation_asks_then_complies(aclient: AsyncClient) -> None:
    conv = AsyncConversation(aclient, KITCHEN)
    asked = await conv.say("Get the mug.")
    assert (asked.decision, asked.utterance) == ("ask", WHICH_MUG)
    done = await conv.say("the red one")
    assert (done.decision, done.utterance, done.goal) == ("comply", "Okay.", "did(self,get(mug1))")
    moved = await conv.say("Put it in the sink.")
    assert moved.goal == "did(self,put(mug1,sink1))"
