#!/usr/bin/env python3
"""A scripted openpi policy server for the Rust client tests.

Speaks openpi's websocket protocol with openpi-client's own msgpack code
(`openpi_client.msgpack_numpy`) and the `websockets` library, like
`openpi/serving/websocket_policy_server.py`: metadata message first, then one binary msgpack
reply per request, a text frame on error.

Normal replies are deterministic: `actions[i, j] = state[j] + 0.01 * i` for j < 6 and
`actions[i, 6] = n`, the number of requests this process has answered before. The reply also
echoes what arrived under `echo` (shapes, dtypes, the prompt and the arrays themselves).

The prompt scripts misbehaviour:
  malformed:<kind>   kind in missing_actions, wrong_shape, nan, short_data, not_msgpack, text_error
  slow:<seconds>     wait before answering normally
  close_after_reply  answer normally, then close the connection

Prints `PORT <n>` on stdout once listening (use --port 0 for a free port). `--log FILE` appends
what each answered request held (prompt, shapes and dtypes) to FILE, one JSON line each.
"""

import argparse
import asyncio
import json
import sys

import numpy as np
import websockets
from openpi_client import msgpack_numpy


def parse_args():
    p = argparse.ArgumentParser()
    p.add_argument("--port", type=int, default=0)
    p.add_argument("--chunk", type=int, default=10, help="action chunk length H")
    p.add_argument("--dtype", choices=["f4", "f8"], default="f8")
    p.add_argument("--metadata", default="{}", help="JSON object sent as the metadata message")
    p.add_argument("--log", help="append one JSON line per answered request (prompt, shapes) to this file")
    return p.parse_args()


ARGS = parse_args()
PACKER = msgpack_numpy.Packer()
STATE = {"requests": 0}


def actions_for(state):
    h = ARGS.chunk
    a = np.zeros((h, 7), dtype=np.float64)
    for i in range(h):
        a[i, :6] = state[:6] + 0.01 * i
        a[i, 6] = STATE["requests"]
    return a.astype("<" + ARGS.dtype)


def describe(x):
    if isinstance(x, np.ndarray):
        return {"shape": list(x.shape), "dtype": x.dtype.str}
    return {"type": type(x).__name__}


def malformed(kind):
    good = np.zeros((ARGS.chunk, 7))
    if kind == "missing_actions":
        return PACKER.pack({"policy_timing": {"infer_ms": 1.0}})
    if kind == "wrong_shape":
        return PACKER.pack({"actions": np.zeros((ARGS.chunk, 8))})
    if kind == "nan":
        good[2, 3] = np.nan
        return PACKER.pack({"actions": good})
    if kind == "short_data":
        doc = msgpack_numpy.pack_array(good)
        doc[b"data"] = doc[b"data"][:-8]
        return PACKER.pack({"actions": doc})
    if kind == "not_msgpack":
        return b"\xc1\xc1"
    raise ValueError(f"unknown malformed kind {kind!r}")


async def handler(ws):
    await ws.send(PACKER.pack(json.loads(ARGS.metadata)))
    async for message in ws:
        obs = msgpack_numpy.unpackb(message)
        prompt = obs.get("prompt", "")
        if prompt.startswith("slow:"):
            await asyncio.sleep(float(prompt.split(":", 1)[1]))
        if prompt == "malformed:text_error":
            await ws.send("Traceback (most recent call last):\nValueError: scripted failure")
            continue
        if prompt.startswith("malformed:"):
            await ws.send(malformed(prompt.split(":", 1)[1]))
            continue
        state = obs["observation/state"]
        reply = {
            "actions": actions_for(state),
            "server_timing": {"infer_ms": 0.0},
            "echo": {
                "image": obs["observation/image"],
                "wrist_image": obs["observation/wrist_image"],
                "state": state,
                "prompt": prompt,
                "shapes": {k: describe(v) for k, v in obs.items()},
            },
        }
        STATE["requests"] += 1
        if ARGS.log:
            with open(ARGS.log, "a") as f:
                f.write(json.dumps({"prompt": prompt, "shapes": reply["echo"]["shapes"]}) + "\n")
        await ws.send(PACKER.pack(reply))
        if prompt == "close_after_reply":
            await ws.close()
            return


async def main():
    async with websockets.serve(handler, "127.0.0.1", ARGS.port, compression=None, max_size=None) as server:
        port = next(iter(server.sockets)).getsockname()[1]
        print(f"PORT {port}", flush=True)
        await asyncio.Future()


if __name__ == "__main__":
    try:
        asyncio.run(main())
    except KeyboardInterrupt:
        sys.exit(0)
