#!/usr/bin/env python3
"""A terminal chat with a robot that asks Scruple before it acts.

Each line you type is what the human says; the robot's answer is printed on a line of its own.
The conversation carries on across lines: an answer to the robot's question goes with the
question ("Get the mug." ... "the red one"), and "it" means what was last acted on. End with
EOF (Ctrl-D); the exit status is then 0.

Usage:
  python chat.py [--url URL] [--scene FILE] [--style diarc|natural] [--verbose]

  --url    the service (default: $SCRUPLE_URL, else http://127.0.0.1:8080)
  --scene  a scene as JSON, as /v1/clarify takes it (default: a kitchen with a red and a blue
           mug, a sink and a fragile vase)
  --verbose  also print the decision and goal, to stderr

Needs the scruple-client package (pip install ./clients/python).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import Any

from scruple_client import Client, ConnectionFailed, Conversation, OptionsBody, SceneBody, ScrupleError

#: The README's kitchen (metres, world frame, z up): everything within the arm's 0.9 m reach.
KITCHEN: dict[str, Any] = {
    "agent": {"id": "self", "position": [0, 0, 0.75], "reach": 0.9},
    "objects": [
        {"id": "mug1", "type": "mug", "attributes": {"color": "red"}, "position": [0.5, 0.1, 0.8]},
        {"id": "mug2", "type": "mug", "attributes": {"color": "blue"}, "position": [0.5, 0.3, 0.8]},
        {"id": "sink1", "type": "sink", "position": [0.6, -0.2, 0.8]},
        {"id": "vase1", "type": "vase", "properties": ["fragile"], "position": [0.6, 0.4, 0.85]},
    ],
}


def load_scene(path: str | None) -> SceneBody:
    """The scene in the file at ``path``, or the kitchen."""
    if path is None:
        return SceneBody.model_validate(KITCHEN)
    with open(path, encoding="utf-8") as f:
        return SceneBody.model_validate(json.load(f))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Chat with a robot that asks Scruple before it acts.")
    parser.add_argument("--url", default=os.environ.get("SCRUPLE_URL") or "http://127.0.0.1:8080")
    parser.add_argument("--scene", help="a scene as JSON (default: a kitchen)")
    parser.add_argument("--style", choices=["diarc", "natural"], help="how the robot speaks (service default: diarc)")
    parser.add_argument("--verbose", action="store_true", help="also print each decision and goal to stderr")
    args = parser.parse_args(argv)

    try:
        scene = load_scene(args.scene)
    except (OSError, ValueError) as e:
        print(f"chat: cannot read the scene {args.scene}: {e}", file=sys.stderr)
        return 2

    interactive = sys.stdin.isatty()
    with Client(args.url) as client:
        conv = Conversation(client, scene, options=OptionsBody(style=args.style) if args.style else None)
        while True:
            if interactive:
                print("you> ", end="", file=sys.stderr, flush=True)
            line = sys.stdin.readline()
            if not line:
                return 0
            words = line.strip()
            if not words:
                continue
            try:
                answer = conv.say(words)
            except ConnectionFailed as e:
                print(f"chat: {e}", file=sys.stderr)
                return 1
            except ScrupleError as e:
                # The service refused the request (say, words over its length limit): say why
                # and go on; the conversation is as it was before the line.
                print(f"chat: {e}", file=sys.stderr)
                continue
            print(answer.utterance, flush=True)
            if args.verbose:
                print(f"  [{answer.decision}] goal: {answer.goal}", file=sys.stderr, flush=True)


if __name__ == "__main__":
    sys.exit(main())
