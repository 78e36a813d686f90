"""The service's own endpoints: its API document, its version, liveness and readiness."""

from __future__ import annotations

import json
import re

from scruple_client import Client

from conftest import openapi_path


def test_the_served_document_is_the_checked_in_one(client: Client) -> None:
    served = client.openapi()
    assert served == json.loads(openapi_path().read_text())
    assert served["openapi"].startswith("3.")
    assert {"/v1/clarify", "/version", "/livez", "/readyz", "/openapi.json"} <= set(served["paths"])


def test_version_says_what_is_running(client: Client) -> None:
    version = client.version()
    assert re.fullmatch(r"\d+\.\d+\.\d+([-+].*)?", version.version), version.version
    assert version.commit is None or re.fullmatch(r"[0-9a-f]{7,40}", version.commit), version.commit
    assert isinstance(version.schema_version, int) and version.schema_version > 0


def test_livez_and_readyz_are_ok_on_a_healthy_service(client: Client) -> None:
    assert client.livez().status == "ok"
    assert client.readyz().status == "ok"
    assert client.healthz().status == "ok"
