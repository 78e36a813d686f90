"""Fixtures: the live service under test, a way to start more, and the paper's norms.

The live service is given by ``SCRUPLE_URL`` (``scripts/python-package.sh`` starts one on a
fresh store and sets it). Tests that need it fail, saying so, when it is not set: nothing is
skipped. Tests that start servers of their own (tokens) use the binary ``SCRUPLE_BIN``
(default: the checkout's ``target/debug/scruple``).
"""

from __future__ import annotations

import os
import subprocess
import time
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path

import pytest

from scruple_client import Client, NormDto

PACKAGE = Path(__file__).resolve().parents[1]
CHECKOUT = PACKAGE.parents[1]


def openapi_path() -> Path:
    """The OpenAPI document the models are checked against: ``SCRUPLE_OPENAPI``, or the
    checkout's ``openapi/openapi.json`` (``../../openapi/openapi.json`` from the package)."""
    given = os.environ.get("SCRUPLE_OPENAPI")
    return Path(given) if given else PACKAGE / ".." / ".." / "openapi" / "openapi.json"


@pytest.fixture(scope="session")
def server_url() -> str:
    """The URL of the live service under test."""
    url = os.environ.get("SCRUPLE_URL", "").strip()
    if not url:
        pytest.fail(
            "SCRUPLE_URL is not set: these tests need a live Scruple. Run scripts/python-package.sh, "
            "or start `scruple serve --listen 127.0.0.1:0 --database-url sqlite:///tmp/s.db` and "
            "export SCRUPLE_URL=http://ADDR (ADDR from its `listening on ADDR` line).",
            pytrace=False,
        )
    return url


@pytest.fixture
def client(server_url: str) -> Iterator[Client]:
    """A client of the live service (with ``SCRUPLE_TOKEN`` as its token, if set)."""
    with Client(server_url, token=os.environ.get("SCRUPLE_TOKEN") or None) as c:
        yield c


#: The paper's norms: destroying and stealing are forbidden, and so is having got the fragile
#: vase (``object3``).
PAPER_NORMS = [
    {"kind": "forbidden_action", "action": "destroy", "note": "destroying any object is forbidden"},
    {"kind": "forbidden_state", "state": "did(self,get(object3))", "note": "the fragile vase may not be got"},
    {"kind": "forbidden_action", "action": "steal", "note": "stealing is forbidden"},
]


@pytest.fixture
def paper_norms(client: Client) -> list[NormDto]:
    """Empties the live service's norm set, then adds the paper's norms one by one."""
    client.put_norm_set([])
    return [client.create_norm(norm) for norm in PAPER_NORMS]


@pytest.fixture(scope="session")
def scruple_binary() -> Path:
    """The ``scruple`` binary for tests that start a server of their own."""
    path = Path(os.environ.get("SCRUPLE_BIN") or CHECKOUT / "target" / "debug" / "scruple")
    if not os.access(path, os.X_OK):
        pytest.fail(f"no scruple binary at {path}: build it, or set SCRUPLE_BIN", pytrace=False)
    return path


@contextmanager
def running_server(binary: Path, workdir: Path, *args: str) -> Iterator[str]:
    """Starts ``scruple serve`` on a free port and a fresh SQLite store in ``workdir`` with the
    extra ``args``; yields its URL; stops it with SIGTERM (it drains and exits 0)."""
    workdir.mkdir(parents=True, exist_ok=True)
    out = workdir / "stdout"
    err = workdir / "stderr"
    with out.open("wb") as stdout, err.open("wb") as stderr:
        process = subprocess.Popen(
            [str(binary), "serve", "--listen", "127.0.0.1:0",
             "--database-url", f"sqlite://{workdir}/scruple.db", *args],
            stdout=stdout,
            stderr=stderr,
        )
    try:
        address = None
        deadline = time.monotonic() + 15
        while time.monotonic() < deadline and address is None:
            for line in out.read_text().splitlines():
                if line.startswith("listening on "):
                    address = line.removeprefix("listening on ").strip()
            if address is None:
                if process.poll() is not None:
                    break
                time.sleep(0.05)
        if address is None:
            raise RuntimeError(f"scruple serve printed no `listening on` line; stderr: {err.read_text()[-2000:]}")
        yield f"http://{address}"
    finally:
        process.terminate()
        try:
            assert process.wait(timeout=15) == 0, f"scruple serve exited {process.returncode} on SIGTERM"
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
            raise


@pytest.fixture
def start_server(scruple_binary: Path, tmp_path: Path) -> Iterator[Callable[..., str]]:
    """A function that starts one more ``scruple serve`` (fresh store, free port, the given
    extra flags) and returns its URL; every server it started is stopped after the test."""
    with ExitStack() as stack:
        count = 0

        def start(*args: str) -> str:
            nonlocal count
            count += 1
            return stack.enter_context(running_server(scruple_binary, tmp_path / f"server{count}", *args))

        yield start
