#!/usr/bin/env python3
"""Action-Sketcher behind openpi's websocket protocol, for `vifo run --model-profile action-sketcher`.

Action-Sketcher has no server: its LIBERO evaluation (`run_libero_example.py` in
FlagOpen/Action-Sketcher, pi0 on LeRobot) runs the model in-process in a See-Think-Sketch-Act
loop. This adapter runs that loop for one request with the repository's own functions:

  inference.load_policy(checkpoint)  (bfloat16 on CUDA);  denormalize = create_denormalizer(
      load_action_stats(checkpoint))
  per episode:  session = {main_task, current_prompt = task, ref_0_rgb = None};
                inference.reset_session(task)
  per request:  state float32 (8,); base/wrist = script_frame(raw frame), as the script builds them;
                repeat inference.inference(prompt, {base_0_rgb, left_wrist_0_rgb, ref_0_rgb}, state,
                do_sample=False, temperature=0.2, max_new_tokens=768, reset=True):
                  an action -> return denormalize(action[:, :7]) (the whole chunk is executed);
                  reasoning -> extract_two_answers, create_prompt, draw the visual prompts on the
                  reference image (draw_vp.visualize_generated_prompts), reset_session, ask again;
                  unparsable reasoning -> error (the script ends the episode there).

The client (`--model-profile action-sketcher`) sends robosuite's raw frames at 224x224 (the
script's env renders 224; run `vifo run --size 224` to skip the resize) and executes the whole
chunk before asking again. Differences that remain (documented, not hidden): the script waits 20
no-op steps (LIBERO-VIFO settles 10) and runs up to 500 steps in every suite (LIBERO-VIFO gives
each suite LIBERO's budget: 220, 280, 300, 520).

Real weights are the user's step:
  git clone https://github.com/FlagOpen/Action-Sketcher && cd Action-Sketcher  # install per README
  PYTHONPATH=. python /path/to/serving/action_sketcher_server.py --checkpoint ./checkpoint --port 8000
`--stand-in` serves a fixed chunk instead of the model (tests; no model code needed).
"""

import argparse
import datetime
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import openpi_ws  # noqa: E402

# The stand-in's chunk: four rows, LIBERO's convention (the script does not convert the gripper).
STAND_IN_CHUNK = [[0.001 * (i + 1), 0.0, -0.002, 0.0, 0.0, 0.0, -1.0] for i in range(4)]


def script_frame(raw):
    """The frame the script feeds the model, from robosuite's raw (bottom-up, HWC) frame: its env
    wrapper flips the rows and transposes to CHW (CleanDiffuser `cleandiffuser/env/libero/
    libero_env.py`: `raw[::-1].transpose(2, 0, 1)`), then `run_libero_example.py` reverses the
    last axis (`obs["agentview_image"][:, :, ::-1]`, meant as BGR->RGB but flipping the
    columns): the usual 180-degree rotation of LIBERO evaluations, in CHW."""
    return np.ascontiguousarray(raw[::-1].transpose(2, 0, 1)[:, :, ::-1])


class ActionSketcher:
    def __init__(self, checkpoint, max_turns):
        import inference
        import torch
        from draw_vp import visualize_generated_prompts
        from run_libero_example import create_denormalizer, create_prompt, extract_two_answers, load_action_stats

        self.torch, self.inference = torch, inference
        self.draw, self.create_prompt, self.extract = visualize_generated_prompts, create_prompt, extract_two_answers
        policy = inference.load_policy(checkpoint)
        if torch.cuda.is_available():
            policy.to(dtype=torch.bfloat16)
            self.device = "cuda"
        else:
            self.device = "cpu"
        self.denormalize = create_denormalizer(load_action_stats(checkpoint))
        self.max_turns = max_turns
        self.session = None

    def reset(self, task):
        self.session = {"main_task": task, "current_prompt": task, "ref_0_rgb": None}
        self.inference.reset_session(task)

    def act(self, obs):
        torch, s = self.torch, self.session
        if s is None:
            raise RuntimeError("no episode started (the first request must carry reset: true)")
        state = np.asarray(obs["observation/state"], dtype=np.float32)
        base = script_frame(obs["observation/image"])
        wrist = script_frame(obs["observation/wrist_image"])
        if s["ref_0_rgb"] is None:
            s["ref_0_rgb"] = base.copy()
        state_tensor = torch.from_numpy(state).to(self.device, dtype=torch.bfloat16)[None, None, :]
        for _ in range(self.max_turns):
            image_obs = {"base_0_rgb": base, "left_wrist_0_rgb": wrist, "ref_0_rgb": s["ref_0_rgb"]}
            result = self.inference.inference(prompt=s["current_prompt"], image_obs=image_obs, state=state_tensor,
                                              do_sample=False, temperature=0.2, max_new_tokens=768,
                                              device=self.device, reset=True)
            if result["is_action"]:
                actions = result["action"].to(dtype=torch.float32).cpu()[:, :7]
                return self.denormalize(actions).numpy()
            text = result["text"]
            subtask, prompts = self.extract(text)
            if not (subtask and prompts):
                raise RuntimeError(f"could not extract a subtask and visual prompts from: {text[:200]!r}")
            stamp = datetime.datetime.now().strftime("%Y%m%d_%H%M%S_%f")
            annotated = self.draw(image_tensor=torch.from_numpy(base), generated_text=text,
                                  output_filename=f"sketch_{stamp}.png")
            s["current_prompt"] = self.create_prompt(main_task=s["main_task"], subtask=subtask,
                                                     visual_reasoning_text=prompts)
            if annotated is not None:
                s["ref_0_rgb"] = np.transpose(annotated, (2, 0, 1))
            self.inference.reset_session(s["current_prompt"])
        raise RuntimeError(f"no action after {self.max_turns} reasoning turns")


class StandIn:
    """A fixed chunk; logs each episode reset on stderr (`RESET <task>`)."""

    def reset(self, task):
        print(f"RESET {task}", file=sys.stderr, flush=True)

    def act(self, obs):
        if obs["observation/image"].shape != (224, 224, 3):
            raise ValueError(f"observation/image is {obs['observation/image'].shape}, the profile sends 224x224")
        return np.array(STAND_IN_CHUNK)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--checkpoint", help="Action-Sketcher checkpoint folder (with norm_stats.json)")
    p.add_argument("--max-turns", type=int, default=8, help="reasoning turns per request before giving up")
    p.add_argument("--host", default="0.0.0.0")
    p.add_argument("--port", type=int, default=8000)
    p.add_argument("--stand-in", action="store_true", help="serve a fixed chunk instead of the model")
    args = p.parse_args()
    if args.stand_in:
        backend = StandIn()
    elif args.checkpoint:
        backend = ActionSketcher(args.checkpoint, args.max_turns)
    else:
        p.error("give --checkpoint (run inside the Action-Sketcher repository) or --stand-in")
    openpi_ws.serve(backend, args.host, args.port)


if __name__ == "__main__":
    main()
