"""``Client`` and ``AsyncClient``: every REST call of Scruple, over httpx.

Owns: building each call (method, path, body, headers) once, in ``_Calls``, and running it
synchronously or asynchronously; the bearer token on every request; errors as exceptions.
Must not: keep state between calls (the service is stateless; ``Conversation`` keeps a dialogue).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Generic, Literal, TypeVar
from urllib.parse import quote

import httpx
from pydantic import BaseModel, TypeAdapter, ValidationError

from .errors import ConnectionFailed, UnexpectedResponse, error_for
from .models import (
    Action,
    AuditPageDto,
    CheckDto,
    DecisionDto,
    Health,
    NormBody,
    NormDto,
    NormSetDto,
    VersionInfo,
)

__all__ = ["Client", "AsyncClient", "DEFAULT_URL", "DEFAULT_TIMEOUT"]

#: Where ``scruple serve`` listens by default.
DEFAULT_URL = "http://127.0.0.1:8080"
#: Seconds for each request (connect, write, read); a decision's own deadline is 2 s by default.
DEFAULT_TIMEOUT = 10.0

T = TypeVar("T")
Body = BaseModel | Mapping[str, Any]
NormLike = NormBody | NormDto | Mapping[str, Any]
Mode = Literal["replace", "merge"]


def _base_url(url: str) -> str:
    """``127.0.0.1:PORT`` as ``scruple serve`` prints it, or a full URL; no trailing slash."""
    url = url.strip()
    if "://" not in url:
        url = f"http://{url}"
    return url.rstrip("/")


def _wire(body: Any) -> Any:
    """A model as JSON data without unset members; a mapping or list is sent as given, with
    any model inside it converted the same way."""
    if isinstance(body, BaseModel):
        return body.model_dump(mode="json", by_alias=True, exclude_none=True)
    if isinstance(body, Mapping):
        return {str(k): _wire(v) for k, v in body.items()}
    if isinstance(body, (list, tuple)):
        return [_wire(v) for v in body]
    return body


def _etag(value: int | str | None) -> str | None:
    """An ``If-Match`` value: a revision or version as a number is quoted (``"12"``); a string
    is sent as written (``"12"``, ``"3", "4"``), quoted first when it is bare digits."""
    if value is None:
        return None
    if isinstance(value, bool):
        raise TypeError("if_match is a revision number or an ETag string")
    if isinstance(value, int):
        return f'"{value}"'
    return f'"{value}"' if value.isdigit() else value


def _norm_body(norm: NormLike, *, keep_id: bool) -> Any:
    """What to send for a norm: a stored norm (:class:`NormDto`) as a body, with its id only
    where the id is meant (a norm-set import); a :class:`NormBody` or a mapping as given."""
    if isinstance(norm, NormDto):
        return norm.to_body(keep_id=keep_id)
    if isinstance(norm, NormBody):
        return norm
    return dict(norm)


@dataclass
class _Call(Generic[T]):
    """One REST call: what to send, and how to read a 2xx answer."""

    method: str
    path: str
    parse: Callable[[httpx.Response], T]
    json: Any = None
    params: dict[str, Any] | None = None
    headers: dict[str, str] = field(default_factory=dict)

    @property
    def repeatable(self) -> bool:
        """Whether sending it twice does what sending it once does: the idempotent methods,
        and the two decisions, which never write."""
        return self.method in _IDEMPOTENT or (self.method == "POST" and self.path in _DECIDING)


_IDEMPOTENT = frozenset({"GET", "HEAD", "OPTIONS", "PUT", "DELETE"})
_DECIDING = frozenset({"/v1/clarify", "/v1/check"})


def _model(adapter: TypeAdapter[T]) -> Callable[[httpx.Response], T]:
    def parse(response: httpx.Response) -> T:
        try:
            return adapter.validate_json(response.content)
        except ValidationError as e:
            raise UnexpectedResponse(
                f"{response.request.method} {response.request.url.path} answered {response.status_code} "
                f"with a body that is not what the API says: {e}",
                status=response.status_code,
                body=response.text,
                response=response,
            ) from e

    return parse


def _json(response: httpx.Response) -> Any:
    try:
        return response.json()
    except ValueError as e:
        raise UnexpectedResponse(
            f"{response.request.url.path} answered {response.status_code} with a body that is not JSON",
            status=response.status_code,
            body=response.text,
            response=response,
        ) from e


def _nothing(response: httpx.Response) -> None:
    return None


def _text(response: httpx.Response) -> str:
    return response.text


def _raw(response: httpx.Response) -> httpx.Response:
    return response


_DECISION = _model(TypeAdapter(DecisionDto))
_CHECK = _model(TypeAdapter(CheckDto))
_NORM = _model(TypeAdapter(NormDto))
_NORMS = _model(TypeAdapter(list[NormDto]))
_NORM_SET = _model(TypeAdapter(NormSetDto))
_ACTION = _model(TypeAdapter(Action))
_ACTIONS = _model(TypeAdapter(list[Action]))
_AUDIT = _model(TypeAdapter(AuditPageDto))
_HEALTH = _model(TypeAdapter(Health))
_VERSION = _model(TypeAdapter(VersionInfo))


class _Calls:
    """Every call of the API, described once for both clients."""

    @staticmethod
    def clarify(request: Body) -> _Call[DecisionDto]:
        return _Call("POST", "/v1/clarify", _DECISION, json=_wire(request))

    @staticmethod
    def check(request: Body) -> _Call[CheckDto]:
        return _Call("POST", "/v1/check", _CHECK, json=_wire(request))

    @staticmethod
    def list_norms() -> _Call[list[NormDto]]:
        return _Call("GET", "/v1/norms", _NORMS)

    @staticmethod
    def create_norm(norm: NormLike) -> _Call[NormDto]:
        return _Call("POST", "/v1/norms", _NORM, json=_wire(_norm_body(norm, keep_id=False)))

    @staticmethod
    def get_norm(norm_id: int) -> _Call[NormDto]:
        return _Call("GET", f"/v1/norms/{int(norm_id)}", _NORM)

    @staticmethod
    def replace_norm(norm_id: int, norm: NormLike, if_match: int | str | None) -> _Call[NormDto]:
        headers = {"if-match": tag} if (tag := _etag(if_match)) else {}
        body = _wire(_norm_body(norm, keep_id=False))
        return _Call("PUT", f"/v1/norms/{int(norm_id)}", _NORM, json=body, headers=headers)

    @staticmethod
    def delete_norm(norm_id: int, if_match: int | str | None) -> _Call[None]:
        headers = {"if-match": tag} if (tag := _etag(if_match)) else {}
        return _Call("DELETE", f"/v1/norms/{int(norm_id)}", _nothing, headers=headers)

    @staticmethod
    def get_norm_set() -> _Call[NormSetDto]:
        return _Call("GET", "/v1/norm-set", _NORM_SET)

    @staticmethod
    def put_norm_set(norms: Sequence[NormLike], mode: Mode, if_match: int | str | None) -> _Call[NormSetDto]:
        if isinstance(norms, (str, bytes)) or isinstance(norms, Mapping):
            raise TypeError("norms is a list of norms")
        if mode not in ("replace", "merge"):
            raise ValueError(f"mode is 'replace' or 'merge', not {mode!r}")
        # `replace` is the service's default, so it is not sent: the call then also works
        # against a service that predates `mode`.
        body: dict[str, Any] = {"norms": [_wire(_norm_body(n, keep_id=True)) for n in norms]}
        if mode != "replace":
            body["mode"] = mode
        headers = {"if-match": tag} if (tag := _etag(if_match)) else {}
        return _Call("PUT", "/v1/norm-set", _NORM_SET, json=body, headers=headers)

    @staticmethod
    def list_actions() -> _Call[list[Action]]:
        return _Call("GET", "/v1/actions", _ACTIONS)

    @staticmethod
    def get_action(name: str) -> _Call[Action]:
        return _Call("GET", f"/v1/actions/{_segment(name)}", _ACTION)

    @staticmethod
    def put_action(name: str, action: Body) -> _Call[Action]:
        return _Call("PUT", f"/v1/actions/{_segment(name)}", _ACTION, json=_wire(action))

    @staticmethod
    def delete_action(name: str) -> _Call[None]:
        return _Call("DELETE", f"/v1/actions/{_segment(name)}", _nothing)

    @staticmethod
    def audit(after: int | None, limit: int | None) -> _Call[AuditPageDto]:
        params = {k: v for k, v in (("after", after), ("limit", limit)) if v is not None}
        return _Call("GET", "/v1/audit", _AUDIT, params=params or None)

    @staticmethod
    def healthz() -> _Call[Health]:
        return _Call("GET", "/healthz", _HEALTH)

    @staticmethod
    def livez() -> _Call[Health]:
        return _Call("GET", "/livez", _HEALTH)

    @staticmethod
    def readyz() -> _Call[Health]:
        return _Call("GET", "/readyz", _HEALTH)

    @staticmethod
    def version() -> _Call[VersionInfo]:
        return _Call("GET", "/version", _VERSION)

    @staticmethod
    def openapi() -> _Call[dict[str, Any]]:
        return _Call("GET", "/openapi.json", _json)

    @staticmethod
    def metrics() -> _Call[str]:
        return _Call("GET", "/metrics", _text)


def _segment(name: str) -> str:
    """A verb name as one path segment (percent-encoded, so it cannot reach another route)."""
    return quote(name, safe="")


class _Base:
    def __init__(
        self,
        base_url: str,
        token: str | None,
        headers: Mapping[str, str] | None,
    ) -> None:
        self.base_url = _base_url(base_url)
        self._headers = {"accept": "application/json, application/problem+json"}
        if headers:
            self._headers.update(headers)
        if token is not None:
            self._headers["authorization"] = f"Bearer {token}"

    def _request(self, call: _Call[Any]) -> dict[str, Any]:
        """Keyword arguments of httpx's ``request`` for ``call``."""
        kwargs: dict[str, Any] = {"headers": call.headers}
        if call.json is not None:
            kwargs["content"] = json.dumps(call.json, separators=(",", ":"), ensure_ascii=False).encode()
            kwargs["headers"] = {**call.headers, "content-type": "application/json"}
        if call.params:
            kwargs["params"] = call.params
        return kwargs

    @staticmethod
    def _again(call: _Call[Any], error: httpx.HTTPError, attempt: int) -> bool:
        """Whether to send ``call`` once more after ``error``: only when the service closed a
        kept-alive connection without answering (it closes one after refusing a request
        whose body it did not read) and the call is :attr:`_Call.repeatable`."""
        return attempt == 0 and isinstance(error, httpx.RemoteProtocolError) and call.repeatable

    @staticmethod
    def _finish(call: _Call[T], response: httpx.Response) -> T:
        if not response.is_success:
            raise error_for(response)
        return call.parse(response)


class Client(_Base):
    """A synchronous client of one Scruple service.

    ``base_url`` is the service's address (``http://127.0.0.1:8080``, or ``127.0.0.1:PORT`` as
    ``scruple serve`` prints it). ``token``, when given, is sent as ``Authorization: Bearer`` on
    every request (writes need it once the service has tokens; clarify and check never do).
    ``timeout`` is in seconds for each request. ``transport`` replaces httpx's (for tests).

    Every call returns the parsed answer or raises a :class:`~scruple_client.ScrupleError`
    subclass. Use it as a context manager, or call :meth:`close`.
    """

    def __init__(
        self,
        base_url: str = DEFAULT_URL,
        *,
        token: str | None = None,
        timeout: float = DEFAULT_TIMEOUT,
        headers: Mapping[str, str] | None = None,
        transport: httpx.BaseTransport | None = None,
    ) -> None:
        super().__init__(base_url, token, headers)
        self._http = httpx.Client(base_url=self.base_url, headers=self._headers, timeout=timeout, transport=transport)

    def __enter__(self) -> Client:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Closes the connections this client holds."""
        self._http.close()

    def _run(self, call: _Call[T]) -> T:
        for attempt in (0, 1):
            try:
                response = self._http.request(call.method, call.path, **self._request(call))
                break
            except httpx.HTTPError as e:
                if not self._again(call, e, attempt):
                    raise ConnectionFailed(f"{call.method} {self.base_url}{call.path}: {e}") from e
        return self._finish(call, response)

    def request(
        self,
        method: str,
        path: str,
        *,
        json: Any = None,
        params: Mapping[str, Any] | None = None,
        headers: Mapping[str, str] | None = None,
    ) -> httpx.Response:
        """Sends any request to the service (with the token) and returns the raw response;
        a non-2xx answer raises as every call does. For what this client does not wrap yet."""
        call = _Call(method.upper(), path, _raw, json=json, params=dict(params or {}), headers=dict(headers or {}))
        return self._run(call)

    # Decisions

    def clarify(self, request: Body) -> DecisionDto:
        """``POST /v1/clarify``: decides a directive in a scene (a :class:`ClarifyBody`, or a
        mapping sent as it is) and returns the decision and what the robot says."""
        return self._run(_Calls.clarify(request))

    def check(self, request: Body) -> CheckDto:
        """``POST /v1/check``: checks ground steps, in order from the scene, under the norms in
        force now (a :class:`CheckBody`, or a mapping); says whether all may be done."""
        return self._run(_Calls.check(request))

    # Norms

    def list_norms(self) -> list[NormDto]:
        """``GET /v1/norms``: every stored norm."""
        return self._run(_Calls.list_norms())

    def create_norm(self, norm: NormLike) -> NormDto:
        """``POST /v1/norms``: stores a norm and returns it with its new ``id`` and ``revision``."""
        return self._run(_Calls.create_norm(norm))

    def get_norm(self, norm_id: int) -> NormDto:
        """``GET /v1/norms/{id}``: one norm; its ``revision`` is its ETag. Unknown: NotFound."""
        return self._run(_Calls.get_norm(norm_id))

    def replace_norm(self, norm_id: int, norm: NormLike, *, if_match: int | str | None = None) -> NormDto:
        """``PUT /v1/norms/{id}``: replaces a norm (its id stays). With ``if_match`` (the
        revision read), only if nobody changed it since; else :class:`StaleRevision`."""
        return self._run(_Calls.replace_norm(norm_id, norm, if_match))

    def delete_norm(self, norm_id: int, *, if_match: int | str | None = None) -> None:
        """``DELETE /v1/norms/{id}``: removes a norm; with ``if_match``, only if unchanged."""
        self._run(_Calls.delete_norm(norm_id, if_match))

    def get_norm_set(self) -> NormSetDto:
        """``GET /v1/norm-set``: the whole norm set and its version (a backup)."""
        return self._run(_Calls.get_norm_set())

    def put_norm_set(
        self,
        norms: Sequence[NormLike],
        mode: Mode = "replace",
        if_match: int | str | None = None,
    ) -> NormSetDto:
        """``PUT /v1/norm-set``: imports norms in one transaction, every one validated first.

        ``mode="replace"`` makes the set exactly ``norms``; ``"merge"`` keeps the stored norms
        not named by id (a norm with an id replaces that norm, one without is added). Norms read
        from the service (:class:`NormDto`) keep their ids. ``if_match``: the set's version
        read, so the import happens only if the set has not changed since. Returns the set
        as stored."""
        return self._run(_Calls.put_norm_set(norms, mode, if_match))

    # Verbs

    def list_actions(self) -> list[Action]:
        """``GET /v1/actions``: every verb of the action library."""
        return self._run(_Calls.list_actions())

    def get_action(self, name: str) -> Action:
        """``GET /v1/actions/{name}``: one verb. Unknown: NotFound."""
        return self._run(_Calls.get_action(name))

    def put_action(self, name: str, action: Body) -> Action:
        """``PUT /v1/actions/{name}``: adds or replaces a verb; returns it as stored."""
        return self._run(_Calls.put_action(name, action))

    def delete_action(self, name: str) -> None:
        """``DELETE /v1/actions/{name}``: removes a verb (:class:`Conflict` while another calls it)."""
        self._run(_Calls.delete_action(name))

    # Audit and service

    def audit(self, *, after: int | None = None, limit: int | None = None) -> AuditPageDto:
        """``GET /v1/audit``: a page of changes to norms and verbs, oldest first, with ids above
        ``after``, at most ``limit`` (1..1000)."""
        return self._run(_Calls.audit(after, limit))

    def healthz(self) -> Health:
        """``GET /healthz``: ``status`` ``ok`` when a decision can be made; else :class:`Unavailable`."""
        return self._run(_Calls.healthz())

    def livez(self) -> Health:
        """``GET /livez``: ``status`` ``ok`` whenever the process answers at all."""
        return self._run(_Calls.livez())

    def readyz(self) -> Health:
        """``GET /readyz``: ``status`` ``ok`` when a decision can be made; else :class:`Unavailable`."""
        return self._run(_Calls.readyz())

    def version(self) -> VersionInfo:
        """``GET /version``: the service's version, commit and newest migration applied."""
        return self._run(_Calls.version())

    def openapi(self) -> dict[str, Any]:
        """``GET /openapi.json``: the service's OpenAPI document."""
        return self._run(_Calls.openapi())

    def metrics(self) -> str:
        """``GET /metrics``: the service's metrics, OpenMetrics text."""
        return self._run(_Calls.metrics())


class AsyncClient(_Base):
    """The asynchronous twin of :class:`Client`: the same calls, awaited.

    Use it as an async context manager, or ``await client.aclose()``.
    """

    def __init__(
        self,
        base_url: str = DEFAULT_URL,
        *,
        token: str | None = None,
        timeout: float = DEFAULT_TIMEOUT,
        headers: Mapping[str, str] | None = None,
        transport: httpx.AsyncBaseTransport | None = None,
    ) -> None:
        super().__init__(base_url, token, headers)
        self._http = httpx.AsyncClient(
            base_url=self.base_url, headers=self._headers, timeout=timeout, transport=transport
        )

    async def __aenter__(self) -> AsyncClient:
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.aclose()

    async def aclose(self) -> None:
        """Closes the connections this client holds."""
        await self._http.aclose()

    async def _run(self, call: _Call[T]) -> T:
        for attempt in (0, 1):
            try:
                response = await self._http.request(call.method, call.path, **self._request(call))
                break
            except httpx.HTTPError as e:
                if not self._again(call, e, attempt):
                    raise ConnectionFailed(f"{call.method} {self.base_url}{call.path}: {e}") from e
        return self._finish(call, response)

    async def request(
        self,
        method: str,
        path: str,
        *,
        json: Any = None,
        params: Mapping[str, Any] | None = None,
        headers: Mapping[str, str] | None = None,
    ) -> httpx.Response:
        """Sends any request to the service (with the token) and returns the raw response;
        a non-2xx answer raises as every call does."""
        call = _Call(method.upper(), path, _raw, json=json, params=dict(params or {}), headers=dict(headers or {}))
        return await self._run(call)

    async def clarify(self, request: Body) -> DecisionDto:
        """``POST /v1/clarify``: decides a directive in a scene; see :meth:`Client.clarify`."""
        return await self._run(_Calls.clarify(request))

    async def check(self, request: Body) -> CheckDto:
        """``POST /v1/check``: checks ground steps in order; see :meth:`Client.check`."""
        return await self._run(_Calls.check(request))

    async def list_norms(self) -> list[NormDto]:
        """``GET /v1/norms``: every stored norm."""
        return await self._run(_Calls.list_norms())

    async def create_norm(self, norm: NormLike) -> NormDto:
        """``POST /v1/norms``: stores a norm; returns it with its ``id`` and ``revision``."""
        return await self._run(_Calls.create_norm(norm))

    async def get_norm(self, norm_id: int) -> NormDto:
        """``GET /v1/norms/{id}``: one norm. Unknown: NotFound."""
        return await self._run(_Calls.get_norm(norm_id))

    async def replace_norm(self, norm_id: int, norm: NormLike, *, if_match: int | str | None = None) -> NormDto:
        """``PUT /v1/norms/{id}``: replaces a norm; see :meth:`Client.replace_norm`."""
        return await self._run(_Calls.replace_norm(norm_id, norm, if_match))

    async def delete_norm(self, norm_id: int, *, if_match: int | str | None = None) -> None:
        """``DELETE /v1/norms/{id}``: removes a norm; with ``if_match``, only if unchanged."""
        await self._run(_Calls.delete_norm(norm_id, if_match))

    async def get_norm_set(self) -> NormSetDto:
        """``GET /v1/norm-set``: the whole norm set and its version."""
        return await self._run(_Calls.get_norm_set())

    async def put_norm_set(
        self,
        norms: Sequence[NormLike],
        mode: Mode = "replace",
        if_match: int | str | None = None,
    ) -> NormSetDto:
        """``PUT /v1/norm-set``: imports norms, replacing or merging; see :meth:`Client.put_norm_set`."""
        return await self._run(_Calls.put_norm_set(norms, mode, if_match))

    async def list_actions(self) -> list[Action]:
        """``GET /v1/actions``: every verb of the action library."""
        return await self._run(_Calls.list_actions())

    async def get_action(self, name: str) -> Action:
        """``GET /v1/actions/{name}``: one verb. Unknown: NotFound."""
        return await self._run(_Calls.get_action(name))

    async def put_action(self, name: str, action: Body) -> Action:
        """``PUT /v1/actions/{name}``: adds or replaces a verb; returns it as stored."""
        return await self._run(_Calls.put_action(name, action))

    async def delete_action(self, name: str) -> None:
        """``DELETE /v1/actions/{name}``: removes a verb."""
        await self._run(_Calls.delete_action(name))

    async def audit(self, *, after: int | None = None, limit: int | None = None) -> AuditPageDto:
        """``GET /v1/audit``: a page of changes to norms and verbs, oldest first."""
        return await self._run(_Calls.audit(after, limit))

    async def healthz(self) -> Health:
        """``GET /healthz``: ``ok`` when a decision can be made; else :class:`Unavailable`."""
        return await self._run(_Calls.healthz())

    async def livez(self) -> Health:
        """``GET /livez``: ``ok`` whenever the process answers."""
        return await self._run(_Calls.livez())

    async def readyz(self) -> Health:
        """``GET /readyz``: ``ok`` when a decision can be made; else :class:`Unavailable`."""
        return await self._run(_Calls.readyz())

    async def version(self) -> VersionInfo:
        """``GET /version``: the service's version, commit and newest migration applied."""
        return await self._run(_Calls.version())

    async def openapi(self) -> dict[str, Any]:
        """``GET /openapi.json``: the service's OpenAPI document."""
        return await self._run(_Calls.openapi())

    async def metrics(self) -> str:
        """``GET /metrics``: the service's metrics, OpenMetrics text."""
        return await self._run(_Calls.metrics())
