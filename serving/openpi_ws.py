"""openpi's websocket policy protocol, server side, for the adapters in this folder.

As `openpi/serving/websocket_policy_server.py`: plain websocket (no compression, no size limit,
keep-alive pings off because inference blocks the loop), the metadata map sent first, then one
binary msgpack-numpy request and one reply per inference (`openpi_client.msgpack_numpy`); an
exception is sent back as a text frame holding the traceback, and the connection stays open.

Requests, as `vifo run --model-profile <adapter's profile>` sends them:
  observation/image        uint8 (H, W, 3)  agentview, robosuite's raw row order (bottom-up)
  observation/wrist_image  uint8 (H, W, 3)  robot0_eye_in_hand, likewise
  observation/state        float64 (8,)     eef_pos | axis-angle(eef_quat) | gripper_qpos
  prompt                   str              the task description (LIBERO's, verbatim)
  reset                    bool             first request of an episode
Reply: {"actions": float (H, 7)}; the client converts the gripper per its profile.
"""

import asyncio
import logging
import traceback

import numpy as np


def check_request(obs):
    """Raises ValueError naming the first field that does not have the documented shape."""
    expected = {"observation/image", "observation/wrist_image", "observation/state", "prompt", "reset"}
    if not isinstance(obs, dict) or set(obs) != expected:
        raise ValueError(f"request keys {sorted(obs) if isinstance(obs, dict) else type(obs)}, expected {sorted(expected)}")
    for key in ("observation/image", "observation/wrist_image"):
        x = obs[key]
        if not (isinstance(x, np.ndarray) and x.dtype == np.uint8 and x.ndim == 3 and x.shape[2] == 3):
            raise ValueError(f"{key} must be uint8 (H, W, 3)")
    s = obs["observation/state"]
    if not (isinstance(s, np.ndarray) and s.dtype == np.float64 and s.shape == (8,)):
        raise ValueError("observation/state must be float64 (8,)")
    if not isinstance(obs["prompt"], str) or not isinstance(obs["reset"], bool):
        raise ValueError("prompt must be a str and reset a bool")


def serve(backend, host, port, metadata=None, on_listen=None):
    """Serves `backend` (reset(task) and act(obs) -> (H, 7) array) until interrupted."""
    import websockets
    from openpi_client import msgpack_numpy

    packer = msgpack_numpy.Packer()

    async def handler(ws):
        await ws.send(packer.pack(metadata or {}))
        async for message in ws:
            try:
                obs = msgpack_numpy.unpackb(message)
                check_request(obs)
                if obs["reset"]:
                    backend.reset(obs["prompt"])
                actions = np.asarray(backend.act(obs), dtype=np.float64)
                if actions.ndim != 2 or actions.shape[1] != 7:
                    raise ValueError(f"backend returned actions of shape {actions.shape}, expected (H, 7)")
                await ws.send(packer.pack({"actions": actions}))
            except Exception:  # noqa: BLE001 - the client gets the traceback, as openpi sends it
                logging.exception("inference failed")
                await ws.send(traceback.format_exc())

    async def main():
        async with websockets.serve(handler, host, port, compression=None, max_size=None,
                                    ping_interval=None, ping_timeout=None) as server:
            bound = next(iter(server.sockets)).getsockname()[1]
            print(f"PORT {bound}", flush=True)
            if on_listen:
                on_listen(bound)
            await asyncio.Future()

    asyncio.run(main())
