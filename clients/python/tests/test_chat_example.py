"""``examples/python/chat.py`` run as a user runs it: lines on stdin, one utterance per line on
stdout, the conversation carried across lines, exit 0 at EOF."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from scruple_client import Client, NormDto

from conftest import CHECKOUT
from scenes import LAB, VASE_ASSUMED, WHICH_MUG

CHAT = Path(os.environ.get("SCRUPLE_CHAT") or CHECKOUT / "examples" / "python" / "chat.py")


def chat(url: str, lines: list[str], *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(CHAT), "--url", url, *args],
        input="".join(f"{line}\n" for line in lines),
        capture_output=True,
        text=True,
        timeout=60,
    )


def test_three_turns_in_the_kitchen(server_url: str, client: Client, paper_norms: list[NormDto]) -> None:
    run = chat(server_url, ["Get the mug.", "the red one", "Smash it."])
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [
        WHICH_MUG,
        "Okay.",
        "I cannot destroy the red mug because destroy is forbidden action.",
    ]
    assert run.stderr == ""


def test_a_scene_file_and_a_request_the_service_refuses(
    server_url: str, client: Client, paper_norms: list[NormDto], tmp_path: Path
) -> None:
    scene = tmp_path / "lab.json"
    scene.write_text(json.dumps(LAB))
    run = chat(server_url, ["Get the vase.", "", "Get the " + "very " * 300 + "big vase.", "Point to it."],
               "--scene", str(scene))
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [VASE_ASSUMED, "Okay."]
    assert "/directive/text" in run.stderr, "the refused line is explained, and the chat goes on"


def test_an_unreachable_service_exits_1(tmp_path: Path) -> None:
    run = chat("http://127.0.0.1:9", ["Get the mug."])
    assert run.returncode == 1
    assert run.stdout == ""
    assert "chat:" in run.stderr
