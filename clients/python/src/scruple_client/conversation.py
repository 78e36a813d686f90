"""A dialogue with Scruple, turn by turn, in the human's words.

Owns: what the stateless service needs the client to carry between turns: the scene and
options, the question left open with the request that led to it, and the ``focus`` (objects of
earlier turns, most salient first: what "it" means).
Must not: decide anything itself. Every turn is one ``POST /v1/clarify``, decided afresh by the
service under the norms in force at that moment.

How a turn is sent (the contract's "Follow-ups in words"):

- No question open: the words are a new directive, ``{"directive": {"text": words}}``, with the
  scene, options, speaker and the current focus.
- A question open (``ask``, ``confirm``, or a refusal offering an ``alternative``): the request
  that led to the question is sent again, with ``"answer": {"text": words}`` and the current
  focus. The service reads the words as the answer ("the red one", "the second one", "yes",
  "never mind"), or, when they are a whole directive ("Get the vase."), decides that instead.
- The question stays open while the service asks again, or when it could not place the answer
  (``unresolved`` or ``not_understood`` in reply to it); any other decision ends the exchange,
  and the next words start a new directive.
- After each decision the objects of what was decided (the ``goal``, or the one reading refused)
  go to the front of the focus, so "Put it in the sink." after "Get the red mug." means the mug.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any

from .client import AsyncClient, Client
from .models import AnswerBody, ClarifyBody, DecisionDto, DirectiveBody, OptionsBody, SceneBody

__all__ = ["Conversation", "AsyncConversation", "MAX_FOCUS", "objects_in"]

#: The most object ids the service takes in ``focus``.
MAX_FOCUS = 16

_ATOM = re.compile(r"[^(),\s]+")


def objects_in(term: str, ids: Sequence[str]) -> list[str]:
    """The ids among ``ids`` that ``term`` names, in the order it first names them:
    ``did(self,and(get(mug2),put(mug2,sink1)))`` names ``mug2`` then ``sink1``."""
    known = set(ids)
    found: list[str] = []
    for atom in _ATOM.findall(term):
        if atom in known and atom not in found:
            found.append(atom)
    return found


class _Dialogue:
    """The state both conversations keep, and the one place that reads and updates it."""

    def __init__(
        self,
        scene: SceneBody | Mapping[str, Any],
        *,
        options: OptionsBody | Mapping[str, Any] | None = None,
        speaker: str | None = None,
        speaker_roles: Sequence[str] | None = None,
        context: str | None = None,
        focus: Sequence[str] | None = None,
    ) -> None:
        #: The scene new directives are decided in; replace it as the world changes.
        self.scene: SceneBody = scene if isinstance(scene, SceneBody) else SceneBody.model_validate(dict(scene))
        #: Options sent with every new directive.
        if options is not None and not isinstance(options, OptionsBody):
            options = OptionsBody.model_validate(dict(options))
        self.options: OptionsBody | None = options
        #: Who speaks (the service's default is ``human``), their roles, and the context.
        self.speaker = speaker
        self.speaker_roles = list(speaker_roles) if speaker_roles is not None else None
        self.context = context
        #: Object ids from earlier turns, most salient first.
        self.focus: list[str] = list(focus or [])
        #: The last request sent, and the service's answer to it.
        self.last_request: ClarifyBody | None = None
        self.last_answer: DecisionDto | None = None
        #: The question the robot asked and the human has not yet answered, in its words.
        self.question: str | None = None
        self._pending: ClarifyBody | None = None
        self._readings: frozenset[str] = frozenset()

    @property
    def pending_request(self) -> ClarifyBody | None:
        """The request whose decision asked :attr:`question`: the next words answer it."""
        return self._pending

    @property
    def awaiting_answer(self) -> bool:
        """True when the robot asked something and the next words are the human's answer."""
        return self._pending is not None

    def reset(self) -> None:
        """Forgets the open question, the focus and the last turn (a new dialogue, same scene)."""
        self.focus = []
        self.last_request = None
        self.last_answer = None
        self.question = None
        self._pending = None
        self._readings = frozenset()

    def request_for(self, words: str) -> ClarifyBody:
        """The request :meth:`say` sends for ``words``: the answer to the open question, or a
        new directive in words."""
        if self._pending is not None:
            return self._pending.model_copy(
                update={"answer": AnswerBody(text=words), "focus": self._focus_in(self._pending.scene)}
            )
        return ClarifyBody(
            speaker=self.speaker,
            directive=DirectiveBody(text=words),
            scene=self.scene,
            context=self.context,
            options=self.options,
            speaker_roles=self.speaker_roles,
            focus=self._focus_in(self.scene),
        )

    def _focus_in(self, scene: SceneBody) -> list[str] | None:
        # The service refuses an id the scene does not hold: the scene may have changed.
        ids = set(scene.ids())
        kept = [i for i in self.focus if i in ids][:MAX_FOCUS]
        return kept or None

    def record(self, words: str, request: ClarifyBody, answer: DecisionDto) -> None:
        """Takes in the service's ``answer`` to ``request`` (sent for ``words``)."""
        self.last_request = request
        self.last_answer = answer

        decided = [answer.goal] if answer.goal else []
        if not decided and answer.decision == "refuse" and len(answer.interpretations) == 1:
            decided = [answer.interpretations[0].action]
        named: list[str] = []
        for term in decided:
            named += [i for i in objects_in(term, request.scene.ids()) if i not in named]
        if named:
            self.focus = (named + [i for i in self.focus if i not in named])[:MAX_FOCUS]

        answered = request.answer is not None
        if answer.asks:
            readings = frozenset(answer.offered) | ({answer.alternative} if answer.alternative else frozenset())
            if not answered:
                self._pending = request.model_copy(update={"answer": None, "focus": None})
            elif not readings <= self._readings:
                # The words were a whole new directive, decided as such: its question is about
                # that directive, so the next answer goes with it.
                self._pending = request.model_copy(
                    update={"directive": DirectiveBody(text=words), "answer": None, "focus": None}
                )
            # Otherwise a narrower question about the same directive: it is answered with the
            # same request (the service takes one answer per request).
            self.question = answer.utterance
            self._readings = readings
        elif answered and answer.decision in ("unresolved", "not_understood"):
            pass  # The answer could not be placed: the question still stands.
        else:
            self._pending = None
            self.question = None
            self._readings = frozenset()


class Conversation(_Dialogue):
    """A dialogue over a :class:`Client`: ``say`` one line of the human's at a time.

    >>> conv = Conversation(client, scene)
    >>> conv.say("Get the mug.").utterance
    'Do you mean that you want me to get the blue mug or that you want me to get the red mug?'
    >>> conv.say("the red one").decision
    'comply'
    >>> conv.say("Put it in the sink.").goal
    'did(self,put(mug1,sink1))'
    """

    def __init__(
        self,
        client: Client,
        scene: SceneBody | Mapping[str, Any],
        *,
        options: OptionsBody | Mapping[str, Any] | None = None,
        speaker: str | None = None,
        speaker_roles: Sequence[str] | None = None,
        context: str | None = None,
        focus: Sequence[str] | None = None,
    ) -> None:
        super().__init__(
            scene, options=options, speaker=speaker, speaker_roles=speaker_roles, context=context, focus=focus
        )
        self.client = client

    def say(self, words: str) -> DecisionDto:
        """Sends the human's ``words`` (a directive, or the answer to the open question) and
        returns the robot's decision; the conversation then carries the question and focus on.
        A failed call raises and leaves the conversation as it was."""
        request = self.request_for(words)
        answer = self.client.clarify(request)
        self.record(words, request, answer)
        return answer


class AsyncConversation(_Dialogue):
    """The asynchronous twin of :class:`Conversation`, over an :class:`AsyncClient`."""

    def __init__(
        self,
        client: AsyncClient,
        scene: SceneBody | Mapping[str, Any],
        *,
        options: OptionsBody | Mapping[str, Any] | None = None,
        speaker: str | None = None,
        speaker_roles: Sequence[str] | None = None,
        context: str | None = None,
        focus: Sequence[str] | None = None,
    ) -> None:
        super().__init__(
            scene, options=options, speaker=speaker, speaker_roles=speaker_roles, context=context, focus=focus
        )
        self.client = client

    async def say(self, words: str) -> DecisionDto:
        """Sends the human's ``words`` and returns the robot's decision; see :meth:`Conversation.say`."""
        request = self.request_for(words)
        answer = await self.client.clarify(request)
        self.record(words, request, answer)
        return answer
