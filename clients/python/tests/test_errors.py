"""How the clients turn answers into exceptions, and what they put on every request, over a
stand-in transport (httpx.MockTransport). No server is needed; the live tests show the same
against the service."""

from __future__ import annotations

import json

import anyio
import httpx
import pytest

from scruple_client import (
    AsyncClient,
    BadRequest,
    Client,
    Conflict,
    ConnectionFailed,
    Forbidden,
    InvalidField,
    NormsUnavailable,
    NotFound,
    Overloaded,
    ScrupleError,
    ServerError,
    StaleRevision,
    Unauthorized,
    Unavailable,
    UnexpectedResponse,
)


def problem(status: int, type_: str, field: str | None = None, **headers: str) -> httpx.Response:
    body = {"type": type_, "title": type_.rsplit("/", 1)[-1], "status": status, "detail": f"what {type_} says"}
    if field is not None:
        body["field"] = field
    return httpx.Response(
        status, content=json.dumps(body).encode(), headers={"content-type": "application/problem+json", **headers}
    )


def answering(response: httpx.Response) -> Client:
    return Client("http://scruple.test", transport=httpx.MockTransport(lambda request: response))


@pytest.mark.parametrize(
    ("response", "cls"),
    [
        (problem(400, "/problems/malformed-body"), BadRequest),
        (problem(422, "/problems/invalid-field", "/directive/action"), InvalidField),
        (problem(400, "/problems/invalid-field", "/severity"), InvalidField),
        (problem(401, "/problems/unauthenticated"), Unauthorized),
        (problem(403, "/problems/forbidden"), Forbidden),
        (problem(404, "/problems/not-found"), NotFound),
        (problem(409, "/problems/verb-in-use"), Conflict),
        (problem(412, "/problems/stale-revision"), StaleRevision),
        (problem(503, "/problems/overloaded", **{"retry-after": "1"}), Overloaded),
        (problem(503, "/problems/norms-unavailable", **{"retry-after": "1"}), NormsUnavailable),
        (problem(500, "/problems/internal"), ServerError),
    ],
    ids=lambda v: v.__name__ if isinstance(v, type) else None,
)
def test_each_problem_raises_its_class(response: httpx.Response, cls: type[ScrupleError]) -> None:
    with pytest.raises(cls) as raised:
        answering(response).list_norms()
    error = raised.value
    body = response.json()
    assert (error.status, error.type, error.title, error.detail) == (
        body["status"], body["type"], body["title"], body["detail"]
    )
    assert error.field == body.get("field")
    assert error.body == response.text
    assert error.problem is not None and error.problem.status == body["status"]


def test_the_field_and_the_wait_are_in_the_exception() -> None:
    with pytest.raises(InvalidField) as raised:
        answering(problem(422, "/problems/invalid-field", "/directive/arguments/0/type")).list_norms()
    assert raised.value.field == "/directive/arguments/0/type"
    assert "(at /directive/arguments/0/type)" in str(raised.value)
    with pytest.raises(Unavailable) as waited:
        answering(problem(503, "/problems/norms-unavailable", **{"retry-after": "2"})).healthz()
    assert waited.value.retry_after == 2.0
    assert isinstance(waited.value, ServerError)


def test_an_error_that_is_not_json_still_raises_with_its_text() -> None:
    page = b"<html>Bad Gateway from the proxy</html>"
    response = httpx.Response(502, content=page, headers={"content-type": "text/html"})
    with pytest.raises(ServerError) as raised:
        answering(response).healthz()
    error = raised.value
    assert error.status == 502
    assert error.type is None and error.problem is None and error.field is None
    assert error.body == "<html>Bad Gateway from the proxy</html>"
    assert "Bad Gateway from the proxy" in str(error)


def test_an_empty_error_body_still_raises() -> None:
    with pytest.raises(NotFound) as raised:
        answering(httpx.Response(404)).get_norm(7)
    assert raised.value.status == 404
    assert "(empty body)" in str(raised.value)


def test_a_success_whose_body_is_not_the_api_raises_unexpected_response() -> None:
    with pytest.raises(UnexpectedResponse):
        answering(httpx.Response(200, json={"status": 1, "unexpected": True})).version()


def test_an_unreachable_service_raises_connection_failed() -> None:
    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("connection refused", request=request)

    with pytest.raises(ConnectionFailed) as raised:
        Client("http://scruple.test", transport=httpx.MockTransport(refuse)).healthz()
    assert raised.value.status is None


def test_the_token_goes_with_every_request_sync_and_async() -> None:
    seen: list[tuple[str, str, str | None]] = []

    def record(request: httpx.Request) -> httpx.Response:
        seen.append((request.method, request.url.path, request.headers.get("authorization")))
        if request.method == "DELETE":
            return httpx.Response(204)
        if request.url.path == "/v1/norms":
            return httpx.Response(200, json=[])
        return httpx.Response(200, json={"status": "ok"})

    with Client("scruple.test:8080", token="s3cret-token-0123456789", transport=httpx.MockTransport(record)) as c:
        c.list_norms()
        c.healthz()
        c.delete_norm(3, if_match=4)

    async def run() -> None:
        async with AsyncClient("scruple.test:8080", token="s3cret-token-0123456789",
                               transport=httpx.MockTransport(record)) as c:
            await c.readyz()

    anyio.run(run)
    assert [s[2] for s in seen] == ["Bearer s3cret-token-0123456789"] * 4
    assert [(m, p) for m, p, _ in seen] == [("GET", "/v1/norms"), ("GET", "/healthz"), ("DELETE", "/v1/norms/3"),
                                          ("GET", "/readyz")]


def test_no_token_no_header_and_if_match_is_quoted() -> None:
    seen: list[httpx.Request] = []

    def record(request: httpx.Request) -> httpx.Response:
        seen.append(request)
        return httpx.Response(204)

    c = Client("http://scruple.test/", transport=httpx.MockTransport(record))
    c.delete_norm(3, if_match=4)
    c.delete_norm(3, if_match='"4", "5"')
    c.delete_action("put it")
    assert "authorization" not in seen[0].headers
    assert seen[0].headers["if-match"] == '"4"'
    assert seen[1].headers["if-match"] == '"4", "5"'
    assert seen[2].url.raw_path == b"/v1/actions/put%20it"


def test_put_norm_set_sends_merge_and_leaves_replace_to_the_default() -> None:
    bodies: list[dict[str, object]] = []

    def record(request: httpx.Request) -> httpx.Response:
        bodies.append(json.loads(request.content))
        return httpx.Response(200, json={"version": 1, "norms": []})

    c = Client("http://scruple.test", transport=httpx.MockTransport(record))
    c.put_norm_set([{"kind": "forbidden_action", "action": "destroy"}])
    c.put_norm_set([{"kind": "forbidden_action", "action": "destroy"}], mode="merge")
    assert bodies == [
        {"norms": [{"kind": "forbidden_action", "action": "destroy"}]},
        {"norms": [{"kind": "forbidden_action", "action": "destroy"}], "mode": "merge"},
    ]
    with pytest.raises(ValueError, match="mode"):
        c.put_norm_set([], mode="overwrite")  # type: ignore[arg-type]


def dropping_once(answer: httpx.Response) -> tuple[Client, list[str]]:
    """A client whose first request finds its kept-alive connection closed without an answer
    (as the service leaves it after refusing a body it did not read); later ones get ``answer``."""
    sent: list[str] = []

    def handle(request: httpx.Request) -> httpx.Response:
        sent.append(f"{request.method} {request.url.path}")
        if len(sent) == 1:
            raise httpx.RemoteProtocolError("Server disconnected without sending a response.", request=request)
        return answer

    return Client("http://scruple.test", transport=httpx.MockTransport(handle)), sent


def test_a_dropped_connection_is_retried_once_for_a_call_safe_to_repeat() -> None:
    c, sent = dropping_once(httpx.Response(200, json=[]))
    assert c.list_norms() == []
    assert sent == ["GET /v1/norms", "GET /v1/norms"]
    c, sent = dropping_once(httpx.Response(200, json={"version": 1, "norms": []}))
    c.put_norm_set([])
    assert sent == ["PUT /v1/norm-set", "PUT /v1/norm-set"]
    c, sent = dropping_once(httpx.Response(200, json={"permitted": True, "steps": [], "utterance": "Okay.",
                                                      "norm_version": 1}))
    assert c.check({"scene": {"agent": {"position": [0, 0, 0], "reach": 1}}, "steps": ["get(o1)"]}).permitted
    assert sent == ["POST /v1/check", "POST /v1/check"]


def test_a_dropped_connection_is_not_retried_for_a_create() -> None:
    c, sent = dropping_once(httpx.Response(201, json={}))
    with pytest.raises(ConnectionFailed, match="Server disconnected"):
        c.create_norm({"kind": "forbidden_action", "action": "destroy"})
    assert sent == ["POST /v1/norms"], "a create that may have been stored is never sent twice"


def test_a_timeout_is_not_retried() -> None:
    sent: list[str] = []

    def slow(request: httpx.Request) -> httpx.Response:
        sent.append(request.url.path)
        raise httpx.ReadTimeout("timed out", request=request)

    with pytest.raises(ConnectionFailed, match="timed out"):
        Client("http://scruple.test", transport=httpx.MockTransport(slow)).healthz()
    assert sent == ["/healthz"]
