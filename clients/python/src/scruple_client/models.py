"""Typed bodies of Scruple's REST API, one class per schema of ``openapi/openapi.json``.

Owns: the shape of what goes over the wire, named exactly as the OpenAPI document names it
(class names are the schema names, field names the property names).
Must not: talk to the network, or decide anything the service decides.

Two kinds of model:

- Request models (``ClarifyBody``, ``NormBody``, ...) serialise with :meth:`WireModel.wire`,
  which leaves out every field that was not set, so no ``null`` is ever sent for it. Where the
  service refuses unknown members (``additionalProperties: false``) they refuse them too, so a
  misspelt option fails here rather than as a 422; scenes, objects and the agent accept extra
  members, as the service does (perception pipelines attach their own).
- Response models (``DecisionDto``, ``NormDto``, ...) accept and keep members they do not know
  (in ``model_extra``), so a newer service that adds fields does not break an older client.

``Action`` and ``Method`` are both sent and received; they accept unknown members for that reason.
``tests/test_drift.py`` checks every class here against the document.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

__all__ = [
    "Scalar",
    "Position",
    "Rotation",
    "WireModel",
    "Ball",
    "Cuboid",
    "Cylinder",
    "ShapeBody",
    "AgentBody",
    "ObjectBody",
    "PersonBody",
    "SceneBody",
    "RelationBody",
    "ReferenceBody",
    "ScoredBinding",
    "BindingBody",
    "StepArgumentBody",
    "StepBody",
    "DirectiveBody",
    "ChoiceBody",
    "AnswerBody",
    "OptionsBody",
    "ClarifyBody",
    "ReasonDto",
    "InterpretationDto",
    "LimitsDto",
    "ReferenceParseDto",
    "PronounParseDto",
    "StepParseDto",
    "PurposeParseDto",
    "ParseDto",
    "DecisionDto",
    "CheckOptionsBody",
    "CheckBody",
    "StepCheckDto",
    "CheckDto",
    "NormBody",
    "NormDto",
    "NormSetBody",
    "NormSetDto",
    "Method",
    "Action",
    "AuditEntryDto",
    "AuditPageDto",
    "Health",
    "VersionInfo",
    "Problem",
    "QUESTION_DECISIONS",
    "DECISIONS",
]

# An attribute value: a string, or a number or boolean the service takes as its JSON text.
# `bool` and `int` come before `float` so that `3` stays `3` (the service would read `3.0` as
# the text "3.0") and `True` stays `true`.
Scalar = str | bool | int | float

#: A point, metres, world frame (z up).
Position = Annotated[list[float], Field(min_length=3, max_length=3)]
#: A unit quaternion ``[x, y, z, w]``.
Rotation = Annotated[list[float], Field(min_length=4, max_length=4)]

#: Every decision the service makes today. ``DecisionDto.decision`` stays a plain string, so a
#: decision added later parses too.
DECISIONS = (
    "comply",
    "refuse",
    "ask",
    "assume",
    "confirm",
    "explain",
    "unresolved",
    "not_understood",
    "cancelled",
)
#: Decisions that leave a question open for the human to answer.
QUESTION_DECISIONS = ("ask", "confirm")


class WireModel(BaseModel):
    """Base of every model: fields by their wire names, serialised without unset members."""

    model_config = ConfigDict(populate_by_name=True)

    def wire(self) -> dict[str, Any]:
        """This body as JSON-ready data, leaving out every member that is unset or ``None``."""
        return self.model_dump(mode="json", by_alias=True, exclude_none=True)


class _Request(WireModel):
    """A body only ever sent, whose schema refuses unknown members."""

    model_config = ConfigDict(extra="forbid", populate_by_name=True)


class _Open(WireModel):
    """A body sent whose schema takes extra members (scenes, objects, the agent)."""

    model_config = ConfigDict(extra="allow", populate_by_name=True)


class _Response(WireModel):
    """A body received: members this client does not know are kept in ``model_extra``."""

    model_config = ConfigDict(extra="allow", populate_by_name=True)


# --- Scenes ---------------------------------------------------------------------------------


class Ball(_Request):
    """A ball shape."""

    radius: float
    """Metres."""


class Cuboid(_Request):
    """A box shape."""

    half_extents: Annotated[list[float], Field(min_length=3, max_length=3)]
    """Half the box's size along the object's x, y and z, metres."""


class Cylinder(_Request):
    """A cylinder shape, its axis along the object's z."""

    radius: float
    """Metres."""
    half_height: float
    """Half the height along the axis, metres."""


class ShapeBody(_Request):
    """An object's shape, centred on its ``position``: exactly one of ``ball``, ``cuboid``,
    ``cylinder``."""

    ball: Ball | None = None
    cuboid: Cuboid | None = None
    cylinder: Cylinder | None = None

    @model_validator(mode="after")
    def _exactly_one(self) -> ShapeBody:
        given = [name for name in ("ball", "cuboid", "cylinder") if getattr(self, name) is not None]
        if len(given) != 1:
            raise ValueError(f"a shape is exactly one of ball, cuboid, cylinder (given: {given or 'none'})")
        return self


class AgentBody(_Open):
    """The robot: where its arm's base is and how far it reaches."""

    id: str | None = None
    position: Position
    """Metres, world frame (z up)."""
    reach: float
    """Metres."""
    gripper_aperture: float | None = None
    """Widest object, metres, the gripper can close around; absent: grasp is not checked."""
    payload: float | None = None
    """Heaviest object, kilograms, the arm can lift; absent: payload is not checked."""
    gripper_size: float | None = None
    """Radius, metres, of the ball the gripper sweeps to an object; absent: not checked."""
    rotation: Rotation | None = None
    """The agent's point of view (x forward, y left, z up) in the world frame; absent: x forward."""


class ObjectBody(_Open):
    """An object of the scene. It yields the facts ``type(id)``, each ``property(id)`` and each
    ``key(id,value)`` of its attributes."""

    id: str
    type: str
    properties: list[str] | None = None
    attributes: dict[str, Scalar] | None = None
    position: Position
    """Centre of the shape, metres, world frame."""
    shape: ShapeBody | None = None
    """Absent: the object is a point."""
    rotation: Rotation | None = None
    mass: float | None = None
    """Kilograms; absent: payload is not checked for this object."""
    names: list[str] | None = None
    """More nouns the object may be called by in words (``["drink"]``)."""


class PersonBody(_Request):
    """A person present: a referent ("Bob", "the child"), a recipient, never an object to handle."""

    id: str
    names: list[str] | None = None
    roles: list[str] | None = None
    position: Position
    """Where the person stands, metres, world frame (z up)."""


class SceneBody(_Open):
    """What the robot perceives: itself, the objects, the people, and facts of its own."""

    agent: AgentBody
    objects: list[ObjectBody] | None = None
    facts: list[str] | None = None
    """Ground facts besides those the objects yield: ``"on(object3,table1)"``."""
    people: list[PersonBody] | None = None

    def ids(self) -> list[str]:
        """The ids of the scene's objects and people, objects first, in order."""
        return [o.id for o in self.objects or []] + [p.id for p in self.people or []]


# --- Directives -----------------------------------------------------------------------------


class RelationBody(_Request):
    """A relation to a landmark: ``on``, ``in``, ``under``, ``near``, ``left_of``, ``right_of``,
    ``behind``, ``in_front_of`` or ``from``."""

    relation: str
    to: ReferenceBody
    """The landmark, a reference of its own."""


class ReferenceBody(_Request):
    """Which object an argument means: ``{"type": "vase"}`` (every match is a candidate), with
    attributes, properties and relations to narrow it, or ``{"id": "object3"}``."""

    id: str | None = None
    type: str | None = None
    attributes: dict[str, Scalar] | None = None
    properties: list[str] | None = None
    relations: list[RelationBody] | None = None
    count: Annotated[int, Field(ge=1, le=32)] | None = None
    """That many of the matches at once; with ``all``, exactly that many must match."""
    all: bool | None = None
    """Every matching object, one step each."""


class ScoredBinding(_Request):
    """A candidate from an upstream resolver with its score (higher is likelier)."""

    id: str
    score: float


#: A candidate binding of a form's variable: an object id, or an id with a score.
BindingBody = str | ScoredBinding


class StepArgumentBody(_Request):
    """An argument of a step: a reference, or ``step`` and ``argument``: the object of argument
    ``argument`` of the earlier step ``step`` (both from 0)."""

    id: str | None = None
    type: str | None = None
    attributes: dict[str, Scalar] | None = None
    properties: list[str] | None = None
    relations: list[RelationBody] | None = None
    count: Annotated[int, Field(ge=1, le=32)] | None = None
    all: bool | None = None
    step: Annotated[int, Field(ge=0)] | None = None
    argument: Annotated[int, Field(ge=0)] | None = None


class StepBody(_Request):
    """One step of a task: a verb, its arguments, and the joiner said between two of them."""

    action: str
    arguments: list[StepArgumentBody] | None = None
    joiner: str | None = None


class DirectiveBody(_Request):
    """What the human asked: ``action`` + ``arguments``, ``form`` + ``bindings``, ``steps``, or
    ``text`` alone (the human's words, read against the scene and the verbs). With ``action``,
    ``form`` or ``steps``, ``text`` is only echoed back."""

    action: str | None = None
    arguments: list[ReferenceBody] | None = None
    form: str | None = None
    """A logical form such as ``did(self,get(X))``, or DIARC's ``want(human,did(self,get(X)))``."""
    bindings: dict[str, list[BindingBody]] | None = None
    """Each variable of ``form`` with its candidates."""
    text: str | None = None
    joiner: str | None = None
    """With ``action``: the word said between its two arguments when not the verb's own."""
    steps: list[StepBody] | None = None


#: A follow-up's choice: a position, from 0, among the question's ``offered``, or
#: ``"alternative"``, the alternative a refusal offered.
ChoiceBody = Annotated[int, Field(ge=0)] | Literal["alternative"]


class AnswerBody(_Request):
    """The human's answer to the question the same request led to: exactly one of ``choice``,
    ``id``, ``reference`` or ``text`` (the human's words: "the red one", "yes", "never mind")."""

    choice: ChoiceBody | None = None
    id: str | None = None
    reference: ReferenceBody | None = None
    text: str | None = None

    @model_validator(mode="after")
    def _exactly_one(self) -> AnswerBody:
        given = [n for n in ("choice", "id", "reference", "text") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError(f"an answer is exactly one of choice, id, reference, text (given: {given or 'none'})")
        return self


class OptionsBody(_Request):
    """How to decide and how to speak. Every member is optional; the service's defaults are the
    paper's behaviour."""

    strategy: Literal["moral", "reflexive"] | None = None
    single_permissible: Literal["assume", "confirm"] | None = None
    style: Literal["diarc", "natural"] | None = None
    max_spoken: Annotated[int, Field(ge=2, le=50)] | None = None
    max_readings: Annotated[int, Field(ge=1, le=100000)] | None = None
    deadline_ms: Annotated[int, Field(ge=1, le=60000)] | None = None
    confirm_above_ratio: Annotated[float, Field(ge=0, lt=1)] | None = None
    soft_norms: Literal["rank", "ignore"] | None = None
    alternatives: Literal["offer", "off"] | None = None


class ClarifyBody(_Request):
    """``POST /v1/clarify``: a directive in a scene. Resend it with ``answer`` set to answer the
    question its decision asked; ``focus`` lists objects from earlier turns (what "it" means)."""

    speaker: str | None = None
    """Who spoke; the service's default is ``"human"``."""
    directive: DirectiveBody
    scene: SceneBody
    context: str | None = None
    """Selects the norms in force; the service's default is ``"default"``."""
    options: OptionsBody | None = None
    speaker_roles: list[str] | None = None
    answer: AnswerBody | None = None
    focus: list[str] | None = None
    """Object ids in the focus of attention from earlier turns, most salient first."""


# --- Decisions ------------------------------------------------------------------------------


class ReasonDto(_Response):
    """Why a reading may not (or should rather not) be done."""

    kind: str
    """``forbidden_action``, ``forbidden_state``, ``unknown_action``, ``unreachable``, ..."""
    detail: str
    """The step or fact at fault, canonical."""
    norm_id: int | None = None
    severity: int | None = None
    words: str
    """The reason in words, in the request's style."""


class InterpretationDto(_Response):
    """One reading of the directive, simulated."""

    action: str
    """Its term, e.g. ``did(self,get(object3))``."""
    description: str
    permissible: bool
    feasible: bool
    reasons: list[ReasonDto]
    plan: list[str]
    """The primitive steps simulated, in order."""
    score: float
    norm_score: int = 0
    """Preferred norms met minus discouraged norms broken, by severity; the service leaves it
    out when 0."""


class LimitsDto(_Response):
    """Which limit was hit, and how much was simulated."""

    reason: str
    """``too_many_readings`` or ``deadline``."""
    readings: int
    simulated: int


class ReferenceParseDto(_Response):
    """One reference in the human's words, and the objects it matches."""

    words: str
    candidates: list[str]


class PronounParseDto(_Response):
    """A pronoun and what it was bound to: ``step``, ``focus`` or ``nothing``."""

    words: str
    argument: int
    bound_to: str
    step: int | None = None
    step_argument: int | None = None
    focus: str | None = None


class StepParseDto(_Response):
    """One step of a task in words."""

    act: str
    form: str
    references: list[ReferenceParseDto]
    pronouns: list[PronounParseDto] = Field(default_factory=list)


class PurposeParseDto(_Response):
    """A purpose as the words said it ("to smash the vase") and the act it names."""

    words: str
    form: str | None = None
    after: int


class ParseDto(_Response):
    """What a directive in words was understood as."""

    act: str
    addressee: str | None = None
    form: str | None = None
    references: list[ReferenceParseDto]
    ignored: list[str]
    unclear: str | None = None
    """Why the words are not a directive, when the decision is ``not_understood``."""
    steps: list[StepParseDto] = Field(default_factory=list)
    purposes: list[PurposeParseDto] = Field(default_factory=list)


class DecisionDto(_Response):
    """The answer of ``POST /v1/clarify``: what the robot decided and what it says."""

    decision: str
    """One of :data:`DECISIONS` (a plain string, so a decision added later still parses)."""
    utterance: str
    speech_act: str
    goal: str | None = None
    """The reading to carry out: set for ``comply`` and ``assume`` only."""
    interpretations: list[InterpretationDto]
    offered: list[str]
    """The readings the utterance proposes, in order (a ``choice`` counts from 0 among them)."""
    limits: LimitsDto | None = None
    norm_version: int
    library_version: int
    text: str | None = None
    """The human's words, as sent in ``directive.text``."""
    parse: ParseDto | None = None
    alternative: str | None = None
    """After a refusal or explanation with alternatives on: the reading offered instead."""

    @property
    def asks(self) -> bool:
        """True when the utterance leaves a question for the human: ``ask``, ``confirm``, or a
        refusal that offers an alternative."""
        return self.decision in QUESTION_DECISIONS or self.alternative is not None


# --- Checks ---------------------------------------------------------------------------------


class CheckOptionsBody(_Request):
    """Options of ``POST /v1/check``."""

    style: Literal["diarc", "natural"] | None = None
    deadline_ms: Annotated[int, Field(ge=1, le=60000)] | None = None


class CheckBody(_Request):
    """``POST /v1/check``: ground steps, checked in order from the current scene."""

    scene: SceneBody
    steps: list[str]
    """Ground action terms such as ``get(object4)``, 1 to 1000."""
    context: str | None = None
    speaker_roles: list[str] | None = None
    options: CheckOptionsBody | None = None


class StepCheckDto(_Response):
    """One step's verdict."""

    step: str
    permissible: bool
    feasible: bool
    reasons: list[ReasonDto]
    plan: list[str]


class CheckDto(_Response):
    """The answer of ``POST /v1/check``."""

    permitted: bool
    """Every step is permissible and feasible under the norms in force now."""
    steps: list[StepCheckDto]
    utterance: str
    norm_version: int
    limits: LimitsDto | None = None


# --- Norms ----------------------------------------------------------------------------------


class NormBody(_Request):
    """A norm as a curator sends it: ``{"kind": "forbidden_action", "action": "destroy"}`` or
    ``{"kind": "forbidden_state", "state": "did(self,get(object3))"}``, optionally with ``when``,
    ``context``, ``severity`` (1..5), ``note``, ``roles`` and ``exempt_roles``."""

    id: int | None = None
    """Kept by a norm-set import; refused on create; on replace it must be the path's id."""
    revision: int | None = None
    """Informational; preconditions go in ``If-Match``."""
    kind: str | None = None
    action: str | None = None
    state: str | None = None
    when: list[str] | None = None
    context: str | None = None
    severity: Annotated[int, Field(ge=1, le=5)] | None = None
    note: str | None = None
    roles: list[str] | None = None
    exempt_roles: list[str] | None = None


class NormDto(_Response):
    """A stored norm, canonical, with its ``id`` and ``revision`` (its ETag)."""

    id: int
    revision: int
    kind: str
    action: str | None = None
    state: str | None = None
    when: list[str]
    context: str | None = None
    severity: int
    note: str | None = None
    roles: list[str] = Field(default_factory=list)
    exempt_roles: list[str] = Field(default_factory=list)

    def to_body(self, *, keep_id: bool = True) -> NormBody:
        """This norm as a body to send back: to a norm-set import (``keep_id``: the id is kept,
        so the import replaces this very norm) or, without the id, to a create or replace."""
        data = {name: getattr(self, name) for name in NormBody.model_fields if name in type(self).model_fields}
        data["revision"] = None
        if not keep_id:
            data["id"] = None
        return NormBody(**{k: v for k, v in data.items() if v is not None})


class NormSetBody(_Request):
    """``PUT /v1/norm-set``: a whole set to import. ``mode`` ``replace`` (the service's default)
    makes the set exactly these norms; ``merge`` keeps stored norms these do not name by id (a
    norm with an id replaces that norm; one without is added with a new id)."""

    version: int | None = None
    """Informational; the precondition goes in ``If-Match``."""
    norms: list[NormBody]
    mode: Literal["replace", "merge"] | None = None


class NormSetDto(_Response):
    """The whole norm set with the version it makes up (its ETag)."""

    version: int
    norms: list[NormDto]


# --- Verbs ----------------------------------------------------------------------------------


class Method(_Response):
    """One way of carrying a verb out; terms are over the verb's parameters."""

    steps: list[str] | None = None
    """Action terms and the word ``itself``; default ``["itself"]``."""
    reach: list[str] | None = None
    grasp: list[str] | None = None
    place: list[str] | None = None
    preconditions: list[str] | None = None
    adds: list[str] | None = None
    removes: list[str] | None = None


class Action(_Response):
    """A verb of the action library: ``GET /v1/actions`` lists them, ``PUT /v1/actions/{name}``
    stores one."""

    name: str | None = None
    parameters: list[str] | None = None
    joiner: str | None = None
    distinct: bool | None = None
    methods: list[Method] | None = None
    words: list[str] | None = None
    joiners: list[str] | None = None
    implied: dict[str, list[str]] | None = None


# --- Audit and service ----------------------------------------------------------------------


class AuditEntryDto(_Response):
    """One change to norms or verbs."""

    id: int
    at: str
    """When it committed: RFC 3339, UTC."""
    actor: str
    subject: str
    operation: str
    target: str | None = None
    before: Any = None
    after: Any = None
    version: int


class AuditPageDto(_Response):
    """A page of the audit trail; pass ``next_after`` as ``after`` for the next page."""

    entries: list[AuditEntryDto]
    next_after: int


class Health(_Response):
    """``/healthz``, ``/livez``, ``/readyz``: ``{"status": "ok"}``."""

    status: str


class VersionInfo(_Response):
    """``GET /version``: the service's version, the commit it was built from, and the newest
    database migration applied."""

    version: str
    commit: str | None = None
    schema_version: int


class Problem(_Response):
    """RFC 9457 problem details: every 4xx and 5xx answer."""

    type: str
    title: str
    status: int
    detail: str
    field: str | None = None
    """A JSON Pointer to the member at fault, when one is: ``/directive/arguments/0/type``."""


RelationBody.model_rebuild()
