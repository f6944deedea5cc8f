#!/usr/bin/env python3
"""Saves a randomly initialised ACT policy with LIBERO-VIFO's LeRobot features (8-D state,
cameras `image` and `wrist_image` at SIDE², 7-D action) and its processors to DIR, so that
upstream LeRobot's `async_inference.policy_server` can load it from disk (no model hub).

Usage: lerobot_stand_in.py DIR [SIDE]
"""

import sys

import torch
from lerobot.configs.types import FeatureType, PolicyFeature
from lerobot.policies.act.configuration_act import ACTConfig
from lerobot.policies.act.modeling_act import ACTPolicy
from lerobot.policies.factory import make_pre_post_processors


def main():
    out = sys.argv[1]
    side = int(sys.argv[2]) if len(sys.argv) > 2 else 256
    torch.manual_seed(0)
    image = PolicyFeature(FeatureType.VISUAL, (3, side, side))
    config = ACTConfig(
        input_features={
            "observation.state": PolicyFeature(FeatureType.STATE, (8,)),
            "observation.images.image": image,
            "observation.images.wrist_image": image,
        },
        output_features={"action": PolicyFeature(FeatureType.ACTION, (7,))},
        device="cpu",
        chunk_size=10,
        n_action_steps=10,
        # No torchvision download; a small model, as only the wire matters.
        pretrained_backbone_weights=None,
        dim_model=64,
        dim_feedforward=128,
        n_encoder_layers=1,
        n_decoder_layers=1,
        n_heads=2,
        use_vae=False,
    )
    ACTPolicy(config).save_pretrained(out)
    pre, post = make_pre_post_processors(config, dataset_stats=None)
    pre.save_pretrained(out)
    post.save_pretrained(out)
    print(f"stand-in ACT policy saved to {out}")


if __name__ == "__main__":
    main()
