#!/usr/bin/env python3
"""A gRPC client of a running Scruple: the same as http_client.py, over gRPC on the same port.

The stubs are generated from proto/scruple/v1/scruple.proto with grpc_tools' bundled protoc
the first time, into a cache directory named by the proto's and grpc_tools' digest
(SCRUPLE_STUBS_DIR, else $XDG_CACHE_HOME/scruple/grpc-stubs, else ~/.cache/scruple/grpc-stubs),
and imported from there afterwards: a changed proto or grpc_tools makes new ones, and nothing
generated is kept in the tree.

Usage: python grpc_client.py 127.0.0.1:PORT   (SCRUPLE_ADMIN_TOKEN: the write token, if any)
"""

import hashlib
import importlib
import os
import shutil
import sys
import tempfile
from importlib import metadata, resources
from pathlib import Path

import grpc
from grpc_tools import protoc

from scene import EXPECTED_DECISION, EXPECTED_UTTERANCE, NORM, REQUEST

PROTO_ROOT = Path(__file__).resolve().parents[2] / "proto"


def stubs_dir():
    """Where this proto's stubs are kept: one directory per proto text and grpc_tools version."""
    proto = (PROTO_ROOT / "scruple" / "v1" / "scruple.proto").read_bytes()
    digest = hashlib.sha256(proto + metadata.version("grpcio-tools").encode()).hexdigest()[:16]
    root = os.environ.get("SCRUPLE_STUBS_DIR")
    if not root:
        cache = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
        root = Path(cache) / "scruple" / "grpc-stubs"
    return Path(root) / digest


def load_stubs():
    """The message and service modules, generated once into stubs_dir() and imported from it.

    Generated into a fresh directory beside it and renamed into place, so two runs at once never
    see half a set: the second rename finds the first's and leaves it.
    """
    target = stubs_dir()
    if not (target / "scruple" / "v1" / "scruple_pb2_grpc.py").is_file():
        target.parent.mkdir(parents=True, exist_ok=True)
        fresh = Path(tempfile.mkdtemp(prefix="generating-", dir=target.parent))
        try:
            generate_stubs(fresh)
            try:
                fresh.rename(target)
            except OSError:
                if not target.is_dir():
                    raise
        finally:
            shutil.rmtree(fresh, ignore_errors=True)
    sys.path.insert(0, str(target))
    return (
        importlib.import_module("scruple.v1.scruple_pb2"),
        importlib.import_module("scruple.v1.scruple_pb2_grpc"),
    )


def generate_stubs(out_dir):
    """Compiles the proto into `out_dir`."""
    well_known = resources.files("grpc_tools") / "_proto"
    status = protoc.main([
        "grpc_tools.protoc",
        f"-I{PROTO_ROOT}",
        f"-I{well_known}",
        f"--python_out={out_dir}",
        f"--grpc_python_out={out_dir}",
        str(PROTO_ROOT / "scruple" / "v1" / "scruple.proto"),
    ])
    if status != 0:
        raise RuntimeError(f"protoc failed with status {status}")


def clarify_request(pb):
    """REQUEST (the REST body) as the proto message: field names and nesting are the same."""
    directive = REQUEST["directive"]
    objects = []
    for o in REQUEST["scene"]["objects"]:
        cylinder = o["shape"]["cylinder"]
        objects.append(pb.Object(
            id=o["id"],
            type=o["type"],
            properties=o["properties"],
            attributes=o["attributes"],
            position=o["position"],
            shape=pb.Shape(cylinder=pb.Cylinder(radius=cylinder["radius"], half_height=cylinder["half_height"])),
        ))
    agent = REQUEST["scene"]["agent"]
    return pb.ClarifyRequest(
        directive=pb.Directive(
            action=directive["action"],
            arguments=[pb.Reference(type=a["type"]) for a in directive["arguments"]],
            text=directive["text"],
        ),
        scene=pb.Scene(
            agent=pb.Agent(id=agent["id"], position=agent["position"], reach=agent["reach"]),
            objects=objects,
        ),
    )


def main(address):
    pb, services = load_stubs()
    token = ()
    if os.environ.get("SCRUPLE_ADMIN_TOKEN"):
        token = (("authorization", f"Bearer {os.environ['SCRUPLE_ADMIN_TOKEN']}"),)
    target = address.split("://", 1)[-1]
    with grpc.insecure_channel(target) as channel:
        try:
            norm = services.NormsStub(channel).CreateNorm(pb.CreateNormRequest(**NORM), metadata=token, timeout=10)
            print(f"norm {norm.id}: {norm.kind} {norm.state}")
            answer = services.ClarifierStub(channel).Clarify(clarify_request(pb), timeout=10)
        except grpc.RpcError as e:
            print(f"grpc_client: {e.code().name}: {e.details()}", file=sys.stderr)
            return 1
    print(f"decision: {answer.decision}")
    print(f"utterance: {answer.utterance}")
    if answer.decision != EXPECTED_DECISION or answer.utterance != EXPECTED_UTTERANCE:
        print(f"grpc_client: expected {EXPECTED_DECISION}: {EXPECTED_UTTERANCE}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
