#!/usr/bin/env python3
"""Scripted test servers, one per serving format of `vifo_protocols::serving`.

    format_servers.py FORMAT [--port 0] [--chunk N] [--lifetime S] [--bad-metadata]

FORMAT is one of
  internvla    InternVLA-A1.5's envelope over openpi's websocket protocol (openpi-client's msgpack)
  openvla-oft  OpenVLA-OFT's `POST /act`, JSON with json_numpy arrays (the json-numpy package)
  xiaomi       Xiaomi-Robotics-0's 4-byte big-endian length + pickle over TCP
  lerobot      LeRobot's async inference gRPC service (grpcio, generic handlers)

Each server listens on 127.0.0.1 only, prints `PORT <n>` once listening and exits after
--lifetime seconds. It checks every field of every request against the format's documented
shape (names, types, dtypes, shapes) and, when a check fails, prints `CHECK FAILED: ...` on
stderr and answers with the format's error.

Actions are scripted: request n (counted from 0 by this process) answers a chunk whose row i
is `state[j] + 0.01 i` for j < 6 and a gripper value in the model's own convention meaning
"open" (LIBERO -1) for even n and "close" (+1) for odd n. The instruction scripts
misbehaviour: `malformed:<kind>` (kinds per format below).
"""

import argparse
import collections
import io
import json
import os
import pickle
import re
import socket
import struct
import sys
import threading
import types
from dataclasses import dataclass, field

import numpy as np

ARGS = None
COUNT = {"n": 0}


class CheckFailed(Exception):
    pass


def expect(cond, message):
    if not cond:
        raise CheckFailed(message)


def check_array(x, name, dtype, shape):
    expect(isinstance(x, np.ndarray), f"{name} is {type(x).__name__}, expected a numpy array")
    expect(x.dtype == np.dtype(dtype), f"{name} has dtype {x.dtype}, expected {dtype}")
    expect(tuple(x.shape) == tuple(shape), f"{name} has shape {x.shape}, expected {shape}")


def check_image(x, name):
    check_array(x, name, np.uint8, (256, 256, 3))


def failed(e):
    print(f"CHECK FAILED: {e}", file=sys.stderr, flush=True)


def scripted_chunk(state, chunk, open_value, close_value, cols=7):
    """Row i: state[:6] + 0.01 i, gripper per request parity; extra columns are 99."""
    a = np.full((chunk, cols), 99.0)
    for i in range(chunk):
        a[i, :6] = np.asarray(state[:6], dtype=np.float64) + 0.01 * i
        a[i, 6] = open_value if COUNT["n"] % 2 == 0 else close_value
    COUNT["n"] += 1
    return a


def kind_of(instruction):
    text = instruction.strip().lower().rstrip(".")
    return text.split(":", 1)[1] if text.startswith("malformed:") else None


# ------------------------------------------------------------------------------------------
# InternVLA: websocket + msgpack envelope

def serve_internvla():
    import asyncio

    import websockets
    from openpi_client import msgpack_numpy

    packer = msgpack_numpy.Packer()
    metadata = {
        "protocol_version": "2.0" if ARGS.bad_metadata else "2.1",
        "preprocessing_owner": "server_canonical",
        "deterministic_inference_preprocess": True,
        "chunk_size": ARGS.chunk,
        "action_dim": 7,
    }

    def check(msg):
        expect(isinstance(msg, dict), "request is not a map")
        expect(set(msg) == {"type", "request_id", "payload"}, f"request keys {sorted(msg)}")
        expect(msg["type"] == "infer", f"type is {msg['type']!r}")
        expect(isinstance(msg["request_id"], str) and re.fullmatch(r"libero-\d+", msg["request_id"]),
               f"request_id is {msg['request_id']!r}")
        p = msg["payload"]
        expect(isinstance(p, dict) and set(p) == {"examples", "do_sample"}, "payload keys")
        expect(p["do_sample"] is False, "do_sample is not False")
        expect(isinstance(p["examples"], list) and len(p["examples"]) == 1, "examples is not a list of 1")
        ex = p["examples"][0]
        expect(set(ex) == {"image", "lang", "task", "state"}, f"example keys {sorted(ex)}")
        expect(isinstance(ex["image"], list) and len(ex["image"]) == 2, "image is not a list of 2")
        check_image(ex["image"][0], "image[0]")
        check_image(ex["image"][1], "image[1]")
        expect(isinstance(ex["lang"], str) and ex["lang"] == ex["task"], "lang and task differ")
        check_array(ex["state"], "state", np.float32, (8,))
        return ex

    def reply(msg):
        try:
            ex = check(msg)
        except CheckFailed as e:
            failed(e)
            return {"status": "error", "ok": False, "type": "inference_result", "error": {"message": str(e)}}
        head = {"status": "ok", "ok": True, "type": "inference_result", "request_id": msg["request_id"],
                "protocol_version": metadata["protocol_version"]}
        chunk = scripted_chunk(ex["state"], ARGS.chunk, 0.9, 0.1).astype(np.float32)[None]
        space = {"low": np.full(7, -10.0, np.float32), "high": np.full(7, 10.0, np.float32)}
        kind = kind_of(ex["lang"])
        if kind is None:
            return {**head, "data": {"actions": chunk, "action_space": space}}
        if kind == "missing_actions":
            return {**head, "data": {"action_space": space}}
        if kind == "wrong_shape":
            return {**head, "data": {"actions": chunk[0]}}
        if kind == "wrong_dtype":
            return {**head, "data": {"actions": chunk.astype(np.int64)}}
        if kind == "error_status":
            return {**head, "status": "error", "ok": False, "error": {"message": "scripted failure"}}
        if kind == "missing_ok":
            return {k: v for k, v in head.items() if k != "ok"} | {"data": {"actions": chunk}}
        if kind == "nan":
            chunk[0, 1, 2] = np.nan
            return {**head, "data": {"actions": chunk}}
        if kind == "not_msgpack":
            return b"\xc1"
        raise ValueError(kind)

    async def handler(ws):
        await ws.send(packer.pack(metadata))
        async for message in ws:
            out = reply(msgpack_numpy.unpackb(message))
            await ws.send(out if isinstance(out, bytes) else packer.pack(out))

    async def main():
        async with websockets.serve(handler, "127.0.0.1", ARGS.port, compression=None, max_size=None,
                                    ping_interval=None, ping_timeout=None) as server:
            print(f"PORT {next(iter(server.sockets)).getsockname()[1]}", flush=True)
            await asyncio.Future()

    asyncio.run(main())


# ------------------------------------------------------------------------------------------
# OpenVLA-OFT: HTTP POST /act, json_numpy

def serve_oft():
    from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

    import json_numpy

    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *args):
            pass

        def send(self, status, body):
            data = body.encode()
            self.send_response(status)
            self.send_header("Content-Type", "application/json")
            self.send_header("Content-Length", str(len(data)))
            self.end_headers()
            self.wfile.write(data)

        def do_POST(self):
            raw = self.rfile.read(int(self.headers["Content-Length"]))
            try:
                expect(self.path == "/act", f"path is {self.path}")
                expect(self.headers.get("Content-Type", "").startswith("application/json"), "not JSON")
                obs = json_numpy.loads(raw)
                expect(isinstance(obs, dict), "body is not an object")
                expect(set(obs) == {"full_image", "wrist_image", "state", "instruction"}, f"keys {sorted(obs)}")
                check_image(obs["full_image"], "full_image")
                check_image(obs["wrist_image"], "wrist_image")
                check_array(obs["state"], "state", np.float64, (8,))
                expect(isinstance(obs["instruction"], str), "instruction is not a str")
            except CheckFailed as e:
                failed(e)
                return self.send(200, json.dumps("error"))
            chunk = scripted_chunk(obs["state"], ARGS.chunk, 1.0, 0.0)
            rows = [chunk[i] for i in range(len(chunk))]
            kind = kind_of(obs["instruction"])
            if kind is None:
                return self.send(200, json_numpy.dumps(rows))
            if kind == "error":
                return self.send(200, json.dumps("error"))
            if kind == "wrong_shape":
                return self.send(200, json_numpy.dumps([r[:6] for r in rows]))
            if kind == "wrong_dtype":
                return self.send(200, json_numpy.dumps([r.astype(np.int64) for r in rows]))
            if kind == "missing_field":
                return self.send(200, json.dumps([{"dtype": "<f8", "shape": [7]}]))
            if kind == "http_500":
                return self.send(500, "Internal Server Error")
            if kind == "not_json":
                return self.send(200, "<html>")
            if kind == "oversize":
                # Past the client's 64 MiB limit; it stops reading, so the write may fail here.
                try:
                    return self.send(200, "[" + " " * (65 << 20) + "]")
                except (BrokenPipeError, ConnectionResetError):
                    return None
            raise ValueError(kind)

    server = ThreadingHTTPServer(("127.0.0.1", ARGS.port), Handler)
    print(f"PORT {server.server_address[1]}", flush=True)
    server.serve_forever()


# ------------------------------------------------------------------------------------------
# Torch tensors without torch: the pickle layout of `Tensor.__reduce_ex__` (rebuild via
# torch._utils._rebuild_tensor_v2 from a storage reduced by TypedStorage.__reduce__ to
# torch.storage._load_from_bytes(<legacy torch.save stream>)), made from stand-in modules.

def _install_fake_torch():
    torch = types.ModuleType("torch")
    utils = types.ModuleType("torch._utils")
    storage = types.ModuleType("torch.storage")
    torch._utils, torch.storage = utils, storage

    def _rebuild_tensor_v2(*args):
        raise RuntimeError("stand-in")

    def _load_from_bytes(b):
        raise RuntimeError("stand-in")

    _rebuild_tensor_v2.__module__, _rebuild_tensor_v2.__qualname__ = "torch._utils", "_rebuild_tensor_v2"
    _load_from_bytes.__module__, _load_from_bytes.__qualname__ = "torch.storage", "_load_from_bytes"
    utils._rebuild_tensor_v2 = _rebuild_tensor_v2
    storage._load_from_bytes = _load_from_bytes
    for name in ("FloatStorage", "DoubleStorage", "LongStorage", "BFloat16Storage"):
        cls = type(name, (), {"__module__": "torch"})
        setattr(torch, name, cls)
    sys.modules.update({"torch": torch, "torch._utils": utils, "torch.storage": storage})
    return torch


class FakeStorage:
    TYPES = {np.dtype(np.float32): "FloatStorage", np.dtype(np.float64): "DoubleStorage",
             np.dtype(np.int64): "LongStorage"}

    def __init__(self, flat):
        self.flat = np.ascontiguousarray(flat)

    def __reduce__(self):
        torch = sys.modules["torch"]
        f = io.BytesIO()
        pickle.dump(0x1950A86A20F9469CFC6C, f, protocol=2)
        pickle.dump(1001, f, protocol=2)
        pickle.dump({"protocol_version": 1001, "little_endian": True,
                     "type_sizes": {"short": 2, "int": 4, "long": 4}}, f, protocol=2)
        p = pickle.Pickler(f, protocol=2)
        kind = getattr(torch, self.TYPES[self.flat.dtype])
        p.persistent_id = lambda o: ("storage", kind, "0", "cpu", self.flat.size, None) if o is self else None
        p.dump(self)
        pickle.dump(["0"], f, protocol=2)
        f.write(struct.pack("<q", self.flat.size))
        f.write(self.flat.tobytes())
        return (sys.modules["torch.storage"]._load_from_bytes, (f.getvalue(),))


class FakeTensor:
    """Pickles like a contiguous CPU torch tensor (or a view `offset` into a bigger storage)."""

    def __init__(self, array, storage=None, offset=0):
        self.array = np.asarray(array)
        self.storage = storage if storage is not None else FakeStorage(self.array.ravel())
        self.offset = offset

    def __reduce_ex__(self, proto):
        shape = tuple(self.array.shape)
        stride = tuple(s // self.array.itemsize for s in self.array.strides)
        return (sys.modules["torch._utils"]._rebuild_tensor_v2,
                (self.storage, self.offset, shape, stride, False, collections.OrderedDict()))


# ------------------------------------------------------------------------------------------
# Xiaomi-Robotics-0: length-prefixed pickles over TCP

def hash_data_to_seed(data):
    """`eval_libero/main.py`'s seed: SHA-256 of canonical JSON, modulo 2**32."""
    import hashlib

    from PIL import Image

    def enc(o):
        if isinstance(o, np.ndarray):
            return {"__type__": "numpy", "dtype": str(o.dtype), "shape": o.shape, "data": o.tobytes().hex()}
        if isinstance(o, Image.Image):
            return {"__type__": "PIL.Image", "mode": o.mode, "size": o.size,
                    "content_hash": hashlib.md5(o.tobytes()).hexdigest()}
        raise TypeError(type(o))

    text = json.dumps(data, default=enc, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return int(hashlib.sha256(text.encode("utf-8")).hexdigest(), 16) % (2 ** 32)


def serve_xiaomi():
    from PIL import Image

    _install_fake_torch()

    def check(req):
        expect(isinstance(req, dict), "request is not a dict")
        expect(list(req) == ["task_id", "state", "base", "wrist_left", "language", "seed"], f"keys {list(req)}")
        expect(req["task_id"] == "libero_all", f"task_id is {req['task_id']!r}")
        check_array(req["state"], "state", np.float64, (32,))
        expect(not req["state"][8:].any(), "state[8:] is not zero")
        for k in ("base", "wrist_left"):
            img = req[k]
            expect(isinstance(img, Image.Image), f"{k} is {type(img).__name__}, expected a PIL image")
            expect(img.mode == "RGB" and img.size == (256, 256), f"{k} is {img.mode} {img.size}")
        lang = req["language"]
        expect(isinstance(lang, str) and lang.endswith(".") and lang[:1] == lang[:1].upper(), f"language {lang!r}")
        expect(lang[:-1] == lang[:-1].capitalize(), f"language {lang!r} is not str.capitalize() + '.'")
        plain = {k: req[k] for k in ("task_id", "state", "base", "wrist_left")} | {"language": lang[:-1]}
        expect(req["seed"] == hash_data_to_seed(plain), f"seed {req['seed']} is not hash_data_to_seed")
        return req

    def answer(req):
        chunk = scripted_chunk(req["state"], ARGS.chunk, -1.0, 1.0, cols=9).astype(np.float32)[None]
        kind = kind_of(req["language"])
        if kind is None:
            return pickle.dumps(FakeTensor(chunk))
        if kind == "wrong_shape":
            return pickle.dumps(FakeTensor(chunk[0]))
        if kind == "wrong_dtype":
            return pickle.dumps(FakeTensor(chunk.astype(np.int64)))
        if kind == "not_tensor":
            return pickle.dumps({"actions": chunk})
        if kind == "short_data":
            whole = pickle.dumps(FakeTensor(chunk))
            return whole[: len(whole) // 2]
        if kind == "close":
            return None
        raise ValueError(kind)

    def recv_all(conn, n):
        data = b""
        while len(data) < n:
            part = conn.recv(n - len(data))
            if not part:
                return None
            data += part
        return data

    srv = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    srv.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    srv.bind(("127.0.0.1", ARGS.port))
    srv.listen(1)
    print(f"PORT {srv.getsockname()[1]}", flush=True)
    while True:
        conn, _ = srv.accept()
        with conn:
            while True:
                head = recv_all(conn, 4)
                if not head:
                    break
                body = recv_all(conn, struct.unpack(">I", head)[0])
                if body is None:
                    break
                try:
                    out = answer(check(pickle.loads(body)))
                except CheckFailed as e:
                    failed(e)
                    out = None
                if out is None:
                    break  # the real server closes the connection when the model raises
                conn.sendall(struct.pack(">I", len(out)) + out)


# ------------------------------------------------------------------------------------------
# LeRobot async inference: gRPC service `transport.AsyncInference`, pickled dataclasses

def _install_fake_lerobot():
    helpers = types.ModuleType("lerobot.async_inference.helpers")

    @dataclass
    class TimedData:
        timestamp: float
        timestep: int

    @dataclass
    class TimedAction(TimedData):
        action: object

    @dataclass
    class TimedObservation(TimedData):
        observation: dict
        must_go: bool = False

    @dataclass
    class RemotePolicyConfig:
        policy_type: str
        pretrained_name_or_path: str
        lerobot_features: dict
        actions_per_chunk: int
        device: str = "cpu"
        rename_map: dict = field(default_factory=dict)

    for cls in (TimedData, TimedAction, TimedObservation, RemotePolicyConfig):
        cls.__module__, cls.__qualname__ = helpers.__name__, cls.__name__
        setattr(helpers, cls.__name__, cls)
    for name in ("lerobot", "lerobot.async_inference"):
        sys.modules[name] = types.ModuleType(name)
    sys.modules[helpers.__name__] = helpers
    return helpers


def _proto_bytes(msg, number):
    """Field `number` (bytes) of a protobuf message; other fields skipped."""
    i, out = 0, b""
    while i < len(msg):
        key, i = _varint(msg, i)
        wire = key & 7
        if wire == 0:
            _, i = _varint(msg, i)
        elif wire == 2:
            n, i = _varint(msg, i)
            if key >> 3 == number:
                out = msg[i:i + n]
            i += n
        else:
            raise CheckFailed(f"unexpected protobuf wire type {wire}")
    return out


def _proto_enum(msg, number):
    i = 0
    while i < len(msg):
        key, i = _varint(msg, i)
        if key & 7 == 0:
            v, i = _varint(msg, i)
            if key >> 3 == number:
                return v
        else:
            n, i = _varint(msg, i)
            i += n
    return 0


def _varint(b, i):
    shift = value = 0
    while True:
        byte = b[i]
        i += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if not byte & 0x80:
            return value, i


def _encode_bytes_field(number, data):
    n, head = len(data), bytes([(number << 3) | 2])
    var = b""
    while True:
        byte = n & 0x7F
        n >>= 7
        var += bytes([byte | (0x80 if n else 0)])
        if not n:
            break
    return head + var + data


def serve_lerobot():
    import queue
    from concurrent import futures

    import grpc

    helpers = _install_fake_lerobot()
    _install_fake_torch()
    state = {"ready": False, "config": None, "wrist": None, "queue": queue.Queue(maxsize=1), "last_timestep": -1}
    names = ["x", "y", "z", "axis_angle_x", "axis_angle_y", "axis_angle_z", "gripper_left", "gripper_right"]

    def ready(request, context):
        state["ready"] = True
        return b""

    def instructions(request, context):
        try:
            expect(state["ready"], "SendPolicyInstructions before Ready")
            cfg = pickle.loads(_proto_bytes(request, 1))
            expect(isinstance(cfg, helpers.RemotePolicyConfig), f"policy setup is {type(cfg).__name__}")
            expect(isinstance(cfg.policy_type, str) and cfg.policy_type, "policy_type")
            expect(isinstance(cfg.pretrained_name_or_path, str) and cfg.pretrained_name_or_path, "pretrained")
            expect(isinstance(cfg.actions_per_chunk, int) and cfg.actions_per_chunk >= 1, "actions_per_chunk")
            expect(isinstance(cfg.device, str), "device")
            expect(getattr(cfg, "rename_map", None) == {}, "rename_map")
            # MolmoAct2's vendored server reads policy_kwargs; upstream LeRobot ignores it.
            kwargs = getattr(cfg, "policy_kwargs", None)
            expect(isinstance(kwargs, dict) and all(isinstance(k, str) and isinstance(v, str) for k, v in kwargs.items()),
                   f"policy_kwargs {kwargs!r}")
            f = cfg.lerobot_features
            cameras = sorted(k for k in f if k.startswith("observation.images."))
            expect(set(f) == {"observation.state", *cameras} and len(cameras) == 2 and "observation.images.image" in cameras,
                   f"lerobot_features keys {sorted(f)}")
            state["wrist"] = next(k for k in cameras if k != "observation.images.image").split(".")[-1]
            print(f"SETUP wrist={state['wrist']} policy_kwargs={json.dumps(kwargs, sort_keys=True)}", file=sys.stderr, flush=True)
            expect(f["observation.state"] == {"dtype": "float32", "shape": (8,), "names": names}, "state feature")
            for k in cameras:
                expect(f[k] == {"dtype": "image", "shape": (256, 256, 3), "names": ["height", "width", "channels"]},
                       f"{k} feature {f[k]}")
            state["config"] = cfg
        except CheckFailed as e:
            failed(e)
            context.abort(grpc.StatusCode.INVALID_ARGUMENT, str(e))
        return b""

    def observations(request_iterator, context):
        data = b""
        try:
            for i, msg in enumerate(request_iterator):
                ts = _proto_enum(msg, 1)
                expect(ts in (1, 2, 3), f"transfer_state {ts}")
                expect((i == 0) == (ts == 1) or ts == 3, f"chunk {i} has transfer_state {ts}")
                data += _proto_bytes(msg, 2)
                if ts == 3:
                    break
            expect(state["config"] is not None, "SendObservations before SendPolicyInstructions")
            obs = pickle.loads(data)
            expect(isinstance(obs, helpers.TimedObservation), f"observation is {type(obs).__name__}")
            expect(isinstance(obs.timestamp, float), "timestamp is not a float")
            expect(isinstance(obs.timestep, int) and obs.timestep > state["last_timestep"], "timestep not increasing")
            expect(obs.must_go is True, "must_go is not True")
            raw = obs.observation
            wrist = state["wrist"]
            expect(set(raw) == set(names) | {"image", wrist, "task"}, f"observation keys {sorted(raw)}")
            for n in names:
                expect(isinstance(raw[n], float), f"{n} is {type(raw[n]).__name__}")
            check_image(raw["image"], "image")
            check_image(raw[wrist], wrist)
            expect(isinstance(raw["task"], str), "task is not a str")
            state["last_timestep"] = obs.timestep
            if not state["queue"].empty():
                state["queue"].get_nowait()
            state["queue"].put(obs)
        except CheckFailed as e:
            failed(e)
            context.abort(grpc.StatusCode.INVALID_ARGUMENT, str(e))
        return b""

    def actions(request, context):
        try:
            obs = state["queue"].get(timeout=1.0)
        except queue.Empty:
            return b""  # LeRobot answers an empty Actions when no observation arrived in time
        raw = obs.observation
        s = np.array([raw[n] for n in names], dtype=np.float32)
        n = state["config"].actions_per_chunk
        chunk = scripted_chunk(s, n, -1.0, 1.0).astype(np.float32)
        storage = FakeStorage(chunk.ravel())
        kind = kind_of(raw["task"])
        t0 = obs.timestamp
        timed = [helpers.TimedAction(t0 + i / 30, obs.timestep + i, FakeTensor(chunk[i], storage, i * 7))
                 for i in range(n)]
        if kind is None:
            return _encode_bytes_field(1, pickle.dumps(timed))
        if kind == "wrong_shape":
            timed = [helpers.TimedAction(t0, obs.timestep + i, FakeTensor(chunk[i, :5])) for i in range(n)]
            return _encode_bytes_field(1, pickle.dumps(timed))
        if kind == "wrong_dtype":
            timed = [helpers.TimedAction(t0, obs.timestep + i, FakeTensor(chunk[i].astype(np.int64))) for i in range(n)]
            return _encode_bytes_field(1, pickle.dumps(timed))
        if kind == "missing_action":
            return _encode_bytes_field(1, pickle.dumps([helpers.TimedData(t0, obs.timestep)]))
        if kind == "error_status":
            context.abort(grpc.StatusCode.INTERNAL, "scripted failure")
        if kind == "empty_reply":
            return b""  # LeRobot's answer when the policy raised on the observation
        raise ValueError(kind)

    ident = lambda b: b  # noqa: E731
    handler = grpc.method_handlers_generic_handler("transport.AsyncInference", {
        "Ready": grpc.unary_unary_rpc_method_handler(ready, ident, ident),
        "SendPolicyInstructions": grpc.unary_unary_rpc_method_handler(instructions, ident, ident),
        "SendObservations": grpc.stream_unary_rpc_method_handler(observations, ident, ident),
        "GetActions": grpc.unary_unary_rpc_method_handler(actions, ident, ident),
    })
    server = grpc.server(futures.ThreadPoolExecutor(max_workers=4))
    server.add_generic_rpc_handlers((handler,))
    port = server.add_insecure_port(f"127.0.0.1:{ARGS.port}")
    server.start()
    print(f"PORT {port}", flush=True)
    server.wait_for_termination()


def main():
    global ARGS
    p = argparse.ArgumentParser()
    p.add_argument("format", choices=["internvla", "openvla-oft", "xiaomi", "lerobot"])
    p.add_argument("--port", type=int, default=0)
    p.add_argument("--chunk", type=int, default=8)
    p.add_argument("--lifetime", type=float, default=600.0, help="exit after this many seconds")
    p.add_argument("--bad-metadata", action="store_true", help="internvla: announce protocol 2.0")
    ARGS = p.parse_args()
    threading.Timer(ARGS.lifetime, lambda: os._exit(0)).start()
    {"internvla": serve_internvla, "openvla-oft": serve_oft, "xiaomi": serve_xiaomi, "lerobot": serve_lerobot}[
        ARGS.format]()


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        sys.exit(0)
