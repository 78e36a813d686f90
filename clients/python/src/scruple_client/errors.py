"""The exceptions a call raises, one class per kind of failure.

Owns: turning a non-2xx answer (RFC 9457 problem+json, or any other body) into an exception
that carries the problem's members, and the single table from status and problem type to class.
Must not: retry, or hide the raw body.
"""

from __future__ import annotations

import json
from typing import Any

import httpx
from pydantic import ValidationError

from .models import Problem

__all__ = [
    "ScrupleError",
    "BadRequest",
    "InvalidField",
    "Unauthorized",
    "Forbidden",
    "NotFound",
    "RequestTimeout",
    "Conflict",
    "StaleRevision",
    "PayloadTooLarge",
    "UnsupportedMediaType",
    "ServerError",
    "Unavailable",
    "Overloaded",
    "NormsUnavailable",
    "ConnectionFailed",
    "UnexpectedResponse",
    "error_for",
]


class ScrupleError(Exception):
    """Anything that kept a call from giving its answer.

    For an answer the service gave: ``status`` (the HTTP status), and from its problem body
    ``type`` (``/problems/invalid-field``), ``title``, ``detail`` and ``field`` (a JSON Pointer to
    the member at fault, or ``None``); ``body`` is the raw text of the answer and ``problem`` the
    parsed problem (``None`` when the body is not a problem). ``retry_after`` is the
    ``Retry-After`` header in seconds, ``request_id`` the ``x-request-id`` header.
    """

    def __init__(
        self,
        message: str,
        *,
        status: int | None = None,
        type: str | None = None,
        title: str | None = None,
        detail: str | None = None,
        field: str | None = None,
        body: str = "",
        problem: Problem | None = None,
        response: httpx.Response | None = None,
    ) -> None:
        super().__init__(message)
        self.status = status
        self.type = type
        self.title = title
        self.detail = detail
        self.field = field
        self.body = body
        self.problem = problem
        self.response = response

    @property
    def retry_after(self) -> float | None:
        """Seconds the service asked to wait before trying again (``Retry-After``), if it said."""
        if self.response is None:
            return None
        value = self.response.headers.get("retry-after")
        try:
            return float(value) if value is not None else None
        except ValueError:
            return None

    @property
    def request_id(self) -> str | None:
        """The ``x-request-id`` of the failed request, to find it in the service's logs."""
        return None if self.response is None else self.response.headers.get("x-request-id")


class BadRequest(ScrupleError):
    """400: the body is not JSON, or the request could not be read."""


class InvalidField(ScrupleError):
    """422 (or a 400 naming a field): a member of the request is wrong; ``field`` points at it."""


class Unauthorized(ScrupleError):
    """401: the request needs a token and none was sent."""


class Forbidden(ScrupleError):
    """403: the token sent is unknown, or may not make this change."""


class NotFound(ScrupleError):
    """404: no such norm or verb, or no such route (``type`` ``/problems/no-route``)."""


class RequestTimeout(ScrupleError):
    """408: the request did not arrive whole in time."""


class Conflict(ScrupleError):
    """409: the change conflicts with what is stored (a verb other verbs call)."""


class StaleRevision(Conflict):
    """412: what ``If-Match`` named has changed since it was read; nothing was written."""


class PayloadTooLarge(ScrupleError):
    """413: the body is over the service's size limit."""


class UnsupportedMediaType(ScrupleError):
    """415: the body is not JSON, or in an encoding the service does not take."""


class ServerError(ScrupleError):
    """5xx: the service failed; nothing a client sent should cause it."""


class Unavailable(ServerError):
    """503: no decision can be made now (the store cannot be read, or the service is busy);
    ``retry_after`` says when to try again. The service fails closed: it never complies instead."""


class Overloaded(Unavailable):
    """503 ``/problems/overloaded``: no turn was free in time."""


class NormsUnavailable(Unavailable):
    """503 ``/problems/norms-unavailable``: the norms or verbs cannot be read."""


class ConnectionFailed(ScrupleError):
    """The service could not be reached, or the connection failed or timed out (no ``status``)."""


class UnexpectedResponse(ScrupleError):
    """A 2xx answer whose body is not what the API document says it is."""


# The single place where a status (and, for 503, the problem's type) becomes a class.
_BY_STATUS: dict[int, type[ScrupleError]] = {
    400: BadRequest,
    401: Unauthorized,
    403: Forbidden,
    404: NotFound,
    408: RequestTimeout,
    409: Conflict,
    412: StaleRevision,
    413: PayloadTooLarge,
    415: UnsupportedMediaType,
    422: InvalidField,
    503: Unavailable,
}
_BY_TYPE: dict[str, type[ScrupleError]] = {
    "/problems/overloaded": Overloaded,
    "/problems/norms-unavailable": NormsUnavailable,
    "/problems/stale-revision": StaleRevision,
}


def _class_for(status: int, problem: Problem | None) -> type[ScrupleError]:
    if problem is not None and problem.type in _BY_TYPE:
        return _BY_TYPE[problem.type]
    if status == 400 and problem is not None and problem.field is not None:
        return InvalidField
    if status in _BY_STATUS:
        return _BY_STATUS[status]
    return ServerError if status >= 500 else ScrupleError


def error_for(response: httpx.Response) -> ScrupleError:
    """The exception for a non-2xx ``response``: its class by status and problem type, its
    members from the problem body when there is one, else the body's text as the detail."""
    text = response.text
    problem: Problem | None = None
    try:
        data: Any = json.loads(text) if text else None
    except ValueError:
        data = None
    if isinstance(data, dict):
        try:
            problem = Problem.model_validate(data)
        except ValidationError:
            problem = None
    cls = _class_for(response.status_code, problem)
    if problem is not None:
        message = f"{problem.status} {problem.title}: {problem.detail}"
        if problem.field is not None:
            message += f" (at {problem.field})"
        return cls(
            message,
            status=response.status_code,
            type=problem.type,
            title=problem.title,
            detail=problem.detail,
            field=problem.field,
            body=text,
            problem=problem,
            response=response,
        )
    reason = response.reason_phrase or "error"
    shown = text.strip() or "(empty body)"
    return cls(
        f"{response.status_code} {reason}: {shown}",
        status=response.status_code,
        title=reason,
        detail=text,
        body=text,
        response=response,
    )
