"""A Python client of Scruple: morally sensitive clarification for robots, over its REST API.

``Client`` and ``AsyncClient`` make every call; ``Conversation`` and ``AsyncConversation`` carry
a dialogue in the human's words; the models are the API's bodies, named as its OpenAPI document
names them; every failure raises a ``ScrupleError`` subclass.
"""

from .client import DEFAULT_TIMEOUT, DEFAULT_URL, AsyncClient, Client
from .conversation import MAX_FOCUS, AsyncConversation, Conversation, objects_in
from .errors import (
    BadRequest,
    Conflict,
    ConnectionFailed,
    Forbidden,
    InvalidField,
    NormsUnavailable,
    NotFound,
    Overloaded,
    PayloadTooLarge,
    RequestTimeout,
    ScrupleError,
    ServerError,
    StaleRevision,
    Unauthorized,
    Unavailable,
    UnexpectedResponse,
    UnsupportedMediaType,
)
from .models import *  # noqa: F403  (the models' own __all__)
from .models import __all__ as _models

__version__ = "0.1.0"

__all__ = [
    "Client",
    "AsyncClient",
    "Conversation",
    "AsyncConversation",
    "objects_in",
    "DEFAULT_URL",
    "DEFAULT_TIMEOUT",
    "MAX_FOCUS",
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
    *_models,
]
