#!/usr/bin/env python3
"""InstructVLA behind openpi's websocket protocol, for `vifo run --model-profile instructvla`.

InstructVLA has no server: its LIBERO evaluation (`deploy/libero/run_libero_eval.py` in
InternRobotics/InstructVLA) loads the model in-process. This adapter does what that script does
for one request, with the repository's own functions:

  cfg = GenerateConfig(pretrained_checkpoint=..., task_suite_name=...)   # the script's defaults
  cfg.unnorm_key = f"{suite}_no_noops";  set_seed_everywhere(cfg.seed)
  model, server = get_model(cfg);  resize_size = get_image_resize_size(cfg)
  per episode:  server.reset(task_description.lower())
  per step:     img = get_libero_image(obs, resize_size), wrist = get_libero_wrist_image(...)
                action = get_action(cfg, model, {"full_image", "wrist_image", "state"}, task, server)

and returns the raw action (1, 7). The client (`--model-profile instructvla`) sends robosuite's
raw frames at 256x256, asks every step (the model ensembles its own chunks, reset per episode)
and applies the script's `normalize_gripper_action(binarize=True)` and `invert_gripper_action`.

Real weights are the user's step:
  git clone https://github.com/InternRobotics/InstructVLA && cd InstructVLA  # install per its README
  PYTHONPATH=. python /path/to/serving/instructvla_server.py \
      --checkpoint /path/to/instructvla_libero.pt --task-suite-name libero_goal --port 8000
(one server per suite: the action statistics depend on it). `--stand-in` serves a fixed action
instead of the model (tests; no model code needed).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import openpi_ws  # noqa: E402

# The stand-in's action, in InstructVLA's raw convention (gripper 1 = open in the RLDS data).
STAND_IN_ACTION = [0.002, -0.001, 0.003, 0.0, 0.0, 0.01, 1.0]


class InstructVla:
    def __init__(self, checkpoint, suite):
        from deploy.libero.libero_utils import get_libero_image, get_libero_wrist_image
        from deploy.libero.run_libero_eval import GenerateConfig
        from deploy.robot_utils import get_action, get_image_resize_size, get_model, set_seed_everywhere

        self.cfg = GenerateConfig(pretrained_checkpoint=checkpoint, task_suite_name=suite)
        self.cfg.unnorm_key = f"{suite}_no_noops"
        set_seed_everywhere(self.cfg.seed)
        self.model, self.server = get_model(self.cfg)
        self.resize_size = get_image_resize_size(self.cfg)
        self._image, self._wrist, self._action = get_libero_image, get_libero_wrist_image, get_action
        self.task = None

    def reset(self, task):
        self.task = task
        self.server.reset(task.lower())

    def act(self, obs):
        raw = {"agentview_image": obs["observation/image"], "robot0_eye_in_hand_image": obs["observation/wrist_image"]}
        observation = {
            "full_image": self._image(raw, self.resize_size),
            "wrist_image": self._wrist(raw, self.resize_size),
            "state": obs["observation/state"],
        }
        action = self._action(self.cfg, self.model, observation, obs["prompt"], self.server)
        return np.asarray(action, dtype=np.float64).reshape(1, -1)[:, :7]


class StandIn:
    """Fixed actions; logs each episode reset on stderr (`RESET <task>`)."""

    def reset(self, task):
        print(f"RESET {task}", file=sys.stderr, flush=True)

    def act(self, obs):
        if obs["observation/image"].shape != (256, 256, 3):
            raise ValueError(f"observation/image is {obs['observation/image'].shape}, the profile sends 256x256")
        return np.array([STAND_IN_ACTION])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--checkpoint", help="InstructVLA checkpoint (.pt)")
    p.add_argument("--task-suite-name", default="libero_goal")
    p.add_argument("--host", default="0.0.0.0")
    p.add_argument("--port", type=int, default=8000)
    p.add_argument("--stand-in", action="store_true", help="serve a fixed action instead of the model")
    args = p.parse_args()
    if args.stand_in:
        backend = StandIn()
    elif args.checkpoint:
        backend = InstructVla(args.checkpoint, args.task_suite_name)
    else:
        p.error("give --checkpoint (run inside the InstructVLA repository) or --stand-in")
    openpi_ws.serve(backend, args.host, args.port)


if __name__ == "__main__":
    main()
