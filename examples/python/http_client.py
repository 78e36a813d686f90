#!/usr/bin/env python3
"""A REST client of a running Scruple: adds the paper's norm, asks it to "Get the vase." and prints
what the robot would say. Exits 1 unless the decision is the paper's (assume the plastic vase).

Usage: python http_client.py 127.0.0.1:PORT   (SCRUPLE_ADMIN_TOKEN: the write token, if any)
"""

import os
import sys

import requests

from scene import EXPECTED_DECISION, EXPECTED_UTTERANCE, NORM, REQUEST, base_url


def main(address):
    base = base_url(address)
    headers = {}
    if os.environ.get("SCRUPLE_ADMIN_TOKEN"):
        headers["Authorization"] = f"Bearer {os.environ['SCRUPLE_ADMIN_TOKEN']}"
    created = requests.post(f"{base}/v1/norms", json=NORM, headers=headers, timeout=10)
    if created.status_code != 201:
        print(f"http_client: adding the norm answered {created.status_code}: {created.text}", file=sys.stderr)
        return 1
    norm = created.json()
    print(f"norm {norm['id']}: {norm['kind']} {norm['state']}")

    answer = requests.post(f"{base}/v1/clarify", json=REQUEST, timeout=10)
    if answer.status_code != 200:
        print(f"http_client: clarify answered {answer.status_code}: {answer.text}", file=sys.stderr)
        return 1
    decision = answer.json()
    print(f"decision: {decision['decision']}")
    print(f"utterance: {decision['utterance']}")
    if decision["decision"] != EXPECTED_DECISION or decision["utterance"] != EXPECTED_UTTERANCE:
        print(f"http_client: expected {EXPECTED_DECISION}: {EXPECTED_UTTERANCE}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    try:
        sys.exit(main(sys.argv[1]))
    except requests.RequestException as e:
        print(f"http_client: {e}", file=sys.stderr)
        sys.exit(1)
