"""The models against the OpenAPI document: a field renamed, added or dropped on either side
fails here, before a user meets it as a 422 or a missing attribute.

The document is ``../../openapi/openapi.json`` from the package (``SCRUPLE_OPENAPI`` overrides
it). No server is needed.

For each model and the schema it stands for:
- every property of the schema is a field of the model (by wire name), and the model has no
  field the schema lacks;
- a property the schema requires is required by the model, and an optional one is optional;
- a property the schema lets be ``null`` is one the model accepts as ``None``;
- a property whose schema is an enum is a ``Literal`` of exactly those values in the model.
Besides: every object schema of the document has a model, and each operation the clients call
exists with the request and answer bodies the clients send and parse.
"""

from __future__ import annotations

import json
from functools import lru_cache
from typing import Any, Literal, get_args, get_origin

import pytest
from pydantic import BaseModel, TypeAdapter, ValidationError

from scruple_client import models as m

from conftest import openapi_path


# (model, JSON Pointer to its schema in the document). Schemas reached through a path are
# those the service has not yet named in the document this package was written against.
PAIRS: list[Any] = [
    (m.ClarifyBody, "/components/schemas/ClarifyBody"),
    (m.DirectiveBody, "/components/schemas/DirectiveBody"),
    (m.ReferenceBody, "/components/schemas/ReferenceBody"),
    (m.RelationBody, "/components/schemas/RelationBody"),
    (m.ScoredBinding, "/components/schemas/BindingBody/oneOf/1"),
    (m.StepBody, "/components/schemas/StepBody"),
    (m.StepArgumentBody, "/components/schemas/StepArgumentBody"),
    (m.AnswerBody, "/components/schemas/AnswerBody"),
    (m.OptionsBody, "/components/schemas/OptionsBody"),
    (m.SceneBody, "/components/schemas/SceneBody"),
    (m.AgentBody, "/components/schemas/AgentBody"),
    (m.ObjectBody, "/components/schemas/ObjectBody"),
    (m.PersonBody, "/components/schemas/PersonBody"),
    (m.ShapeBody, "/components/schemas/ShapeBody"),
    (m.Ball, "/components/schemas/ShapeBody/oneOf/0/properties/ball"),
    (m.Cuboid, "/components/schemas/ShapeBody/oneOf/1/properties/cuboid"),
    (m.Cylinder, "/components/schemas/ShapeBody/oneOf/2/properties/cylinder"),
    (m.DecisionDto, "/components/schemas/DecisionDto"),
    (m.InterpretationDto, "/components/schemas/InterpretationDto"),
    (m.ReasonDto, "/components/schemas/ReasonDto"),
    (m.LimitsDto, "/components/schemas/LimitsDto"),
    (m.ParseDto, "/components/schemas/ParseDto"),
    (m.ReferenceParseDto, "/components/schemas/ReferenceParseDto"),
    (m.StepParseDto, "/components/schemas/StepParseDto"),
    (m.PronounParseDto, "/components/schemas/PronounParseDto"),
    (m.PurposeParseDto, "/components/schemas/PurposeParseDto"),
    (m.CheckBody, "/components/schemas/CheckBody"),
    (m.CheckOptionsBody, "/components/schemas/CheckOptionsBody"),
    (m.CheckDto, "/components/schemas/CheckDto"),
    (m.StepCheckDto, "/components/schemas/StepCheckDto"),
    (m.NormBody, "/components/schemas/NormBody"),
    (m.NormDto, "/components/schemas/NormDto"),
    (m.NormSetBody, "/components/schemas/NormSetBody"),
    (m.NormSetDto, "/components/schemas/NormSetDto"),
    (m.Action, "/components/schemas/Action"),
    (m.Method, "/components/schemas/Method"),
    (m.AuditEntryDto, "/components/schemas/AuditEntryDto"),
    (m.AuditPageDto, "/components/schemas/AuditPageDto"),
    (m.Health, "/components/schemas/Health"),
    (m.Problem, "/components/schemas/Problem"),
    (m.VersionInfo, "/components/schemas/VersionInfo"),
]

# (method, path, request model, success status, answer model): what the clients send and parse.
OPERATIONS: list[Any] = [
    ("post", "/v1/clarify", m.ClarifyBody, "200", m.DecisionDto),
    ("post", "/v1/check", m.CheckBody, "200", m.CheckDto),
    ("get", "/v1/norms", None, "200", list[m.NormDto]),
    ("post", "/v1/norms", m.NormBody, "201", m.NormDto),
    ("get", "/v1/norms/{id}", None, "200", m.NormDto),
    ("put", "/v1/norms/{id}", m.NormBody, "200", m.NormDto),
    ("delete", "/v1/norms/{id}", None, "204", None),
    ("get", "/v1/norm-set", None, "200", m.NormSetDto),
    ("put", "/v1/norm-set", m.NormSetBody, "200", m.NormSetDto),
    ("get", "/v1/actions", None, "200", list[m.Action]),
    ("get", "/v1/actions/{name}", None, "200", m.Action),
    ("put", "/v1/actions/{name}", m.Action, "200", m.Action),
    ("delete", "/v1/actions/{name}", None, "204", None),
    ("get", "/v1/audit", None, "200", m.AuditPageDto),
    ("get", "/healthz", None, "200", m.Health),
    ("get", "/livez", None, "200", m.Health),
    ("get", "/readyz", None, "200", m.Health),
    ("get", "/version", None, "200", m.VersionInfo),
    ("get", "/openapi.json", None, "200", None),
]


def unpack(pair: Any) -> tuple[Any, ...]:
    """The values of a table row, plain or wrapped in ``pytest.param``."""
    return tuple(pair.values) if hasattr(pair, "values") else tuple(pair)


@lru_cache(maxsize=1)
def document() -> dict[str, Any]:
    path = openapi_path()
    try:
        doc: dict[str, Any] = json.loads(path.read_text())
        return doc
    except FileNotFoundError:
        pytest.fail(f"no OpenAPI document at {path} (set SCRUPLE_OPENAPI)", pytrace=False)


def pointer(doc: dict[str, Any], ptr: str) -> Any:
    """The member of ``doc`` at a JSON Pointer (``/components/schemas/X``, ``~1`` for ``/``)."""
    node: Any = doc
    for raw in ptr.lstrip("#").strip("/").split("/"):
        key = raw.replace("~1", "/").replace("~0", "~")
        if isinstance(node, list):
            node = node[int(key)]
        elif isinstance(node, dict) and key in node:
            node = node[key]
        else:
            raise KeyError(f"the document has nothing at {ptr} (no `{key}`)")
    return node


def resolve(schema: Any) -> tuple[dict[str, Any], str | None]:
    """A schema with its ``$ref`` chain followed, and the component name it ends at."""
    name = None
    while isinstance(schema, dict) and "$ref" in schema:
        ref = schema["$ref"]
        name = ref.rsplit("/", 1)[-1]
        schema = pointer(document(), ref)
    return schema, name


def object_shape(schema: dict[str, Any]) -> tuple[dict[str, Any], set[str]]:
    """The properties of an object schema and those it requires; for a ``oneOf`` of objects
    (a shape), every variant's properties, none required (exactly one is given)."""
    if "oneOf" in schema and all("properties" in resolve(v)[0] for v in schema["oneOf"]):
        props: dict[str, Any] = {}
        for variant in schema["oneOf"]:
            props.update(resolve(variant)[0]["properties"])
        return props, set()
    return schema.get("properties", {}), set(schema.get("required", []))


def allows_null(prop: dict[str, Any]) -> bool:
    kinds = prop.get("type")
    if kinds is None and "oneOf" not in prop and "$ref" not in prop:
        return True  # any JSON value
    if kinds == "null" or (isinstance(kinds, list) and "null" in kinds):
        return True
    return any(v.get("type") == "null" for v in prop.get("oneOf", []))


def enum_of(prop: dict[str, Any]) -> set[Any] | None:
    """The values of an enum property (directly, by ``$ref``, or as ``oneOf`` an enum or null)."""
    candidates = [prop] + [v for v in prop.get("oneOf", []) if v.get("type") != "null"]
    for candidate in candidates:
        schema, _ = resolve(candidate)
        if "enum" in schema:
            return set(schema["enum"])
    return None


def literals(annotation: Any) -> set[Any]:
    """Every ``Literal`` value inside a type annotation."""
    if get_origin(annotation) is Literal:
        return set(get_args(annotation))
    found: set[Any] = set()
    for arg in get_args(annotation):
        found |= literals(arg)
    return found


def fields_by_wire_name(model: type[BaseModel]) -> dict[str, Any]:
    return {(f.alias or name): f for name, f in model.model_fields.items()}


def accepts_none(annotation: Any) -> bool:
    try:
        TypeAdapter(annotation).validate_python(None)
        return True
    except ValidationError:
        return False


@pytest.mark.parametrize(("model", "where"), PAIRS, ids=lambda v: v.__name__ if isinstance(v, type) else None)
def test_model_matches_schema(model: type[BaseModel], where: str) -> None:
    try:
        schema, _ = resolve(pointer(document(), where))
    except KeyError as e:
        pytest.fail(f"{model.__name__}: {e.args[0]}", pytrace=False)
    props, required = object_shape(schema)
    fields = fields_by_wire_name(model)
    problems: list[str] = []
    for name in sorted(set(props) - set(fields)):
        problems.append(f"the schema has `{name}`, the model {model.__name__} has no such field")
    for name in sorted(set(fields) - set(props)):
        problems.append(f"the model {model.__name__} has `{name}`, the schema has no such property")
    for name in sorted(set(props) & set(fields)):
        field, prop = fields[name], props[name]
        if (name in required) != field.is_required():
            said = "requires" if name in required else "does not require"
            does = "does" if field.is_required() else "does not"
            problems.append(f"`{name}`: the schema {said} it, the model {does}")
        if allows_null(prop) and not accepts_none(field.annotation):
            problems.append(f"`{name}`: the schema allows null, the model refuses None")
        values = enum_of(prop)
        if values is not None and literals(field.annotation) != values:
            theirs = sorted(literals(field.annotation))
            problems.append(f"`{name}`: the schema's values are {sorted(values)}, the model's {theirs}")
    assert not problems, f"{model.__name__} vs {where}:\n  " + "\n  ".join(problems)


def test_every_object_schema_has_a_model() -> None:
    paired: set[str] = set()
    for pair in PAIRS:
        where = unpack(pair)[1]
        try:
            _, name = resolve(pointer(document(), where))
        except KeyError:
            continue  # reported by its own test
        parts = where.strip("/").split("/")
        paired.add(name or (parts[2] if parts[:2] == ["components", "schemas"] else ""))
    schemas = document()["components"]["schemas"]
    unmodelled = sorted(
        name
        for name, schema in schemas.items()
        if "properties" in schema and name not in paired
    )
    assert not unmodelled, f"object schemas with no model in scruple_client.models: {unmodelled}"


def _refers_to(schema: Any, model: Any) -> bool:
    """Whether a body schema is (or, as a ``oneOf``, admits) the schema ``model`` is paired with."""
    wanted = [unpack(p)[1] for p in PAIRS if unpack(p)[0] is model]
    assert wanted, f"{model} has no pair"
    target = wanted[0]
    target_schema, target_name = resolve(pointer(document(), target))
    schema, name = resolve(schema)
    if name is not None and name == target_name:
        return True
    if schema is target_schema:
        return True
    return any(_refers_to(v, model) for v in schema.get("oneOf", []))


@pytest.mark.parametrize(("method", "path", "request_model", "status", "answer_model"), OPERATIONS)
def test_operation_bodies(method: str, path: str, request_model: Any, status: str, answer_model: Any) -> None:
    operation = document()["paths"].get(path, {}).get(method)
    said = f"{method.upper()} {path}"
    if operation is None:
        pytest.fail(f"the document has no {said}, which the clients call", pytrace=False)
    if request_model is not None:
        body = operation.get("requestBody", {}).get("content", {}).get("application/json", {}).get("schema", {})
        if not _refers_to(body, request_model):
            pytest.fail(f"{said} takes no {request_model.__name__}", pytrace=False)
    if status not in operation["responses"]:
        pytest.fail(f"{said} has no {status} answer", pytrace=False)
    if answer_model is None:
        return
    schema = operation["responses"][status].get("content", {}).get("application/json", {}).get("schema", {})
    if get_origin(answer_model) is list:
        if schema.get("type") != "array" or not _refers_to(schema["items"], get_args(answer_model)[0]):
            pytest.fail(f"{said} does not answer a list of {get_args(answer_model)[0].__name__}", pytrace=False)
    elif not _refers_to(schema, answer_model):
        pytest.fail(f"{said} does not answer {answer_model.__name__}", pytrace=False)

