//! One profile per model: what its own LIBERO evaluation script gives the model and does with
//! the reply, so a served model sees exactly that from our environment.
//!
//! Every profile below cites the script it follows. Images: our frames are upright; robosuite's
//! are bottom-up (`raw[r] = upright[H-1-r]`), and the usual `raw[::-1, ::-1]` "180° rotation" is
//! our upright frame mirrored left–right ([`Orientation::Rotated180`]). Sizes: `None` sends the
//! frame as rendered (LIBERO renders 256×256; run with `--size 256`), `Some(n)` resizes with
//! openpi's `resize_with_pad` (PIL bilinear), as the pi0.5 client does.

use vifo_cues::RgbImage;

use super::Format;
use crate::policy::Observation;
use crate::remote::image::{mirror_left_right, resize_with_pad};

/// How a frame is oriented on the wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Orientation {
    /// robosuite's `obs[...][::-1, ::-1]` (openpi, OpenVLA-OFT, InternVLA, Xiaomi).
    Rotated180,
    /// robosuite's raw order (bottom-up), for adapters that run the model's own
    /// preprocessing on what LIBERO returns.
    Robosuite,
}

/// The proprioceptive vector sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StateLayout {
    /// eef position ‖ axis-angle ‖ finger positions ([`Observation::state8`]).
    Eef8,
    /// [`StateLayout::Eef8`] followed by zeros up to this length (Xiaomi-Robotics-0: 32).
    Eef8Padded(usize),
}

/// How the task description becomes the text the model receives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instruction {
    /// `task.language` verbatim (LIBERO: lower case, no period).
    Verbatim,
    /// Python's `str.capitalize()` then a period (Xiaomi-Robotics-0's `eval_libero/main.py`).
    CapitalizedSentence,
}

/// What the client does with the gripper value the model returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gripper {
    /// Already in LIBERO's convention (−1 open, +1 close).
    AsIs,
    /// OpenVLA's `normalize_gripper_action(binarize=True)` then `invert_gripper_action`:
    /// `-sign(2g - 1)` (the RLDS data uses 0 = close, 1 = open; 0.5 stays 0).
    OpenVlaBinarizeInvert,
    /// InternVLA's LIBERO client: `+1 if g < 0.5 else -1`.
    ThresholdHalfInvert,
}

impl Gripper {
    pub fn apply(self, g: f64) -> f64 {
        match self {
            Gripper::AsIs => g,
            Gripper::OpenVlaBinarizeInvert => {
                let x = 2.0 * g - 1.0;
                // np.sign: exactly 0 stays 0.
                if x > 0.0 {
                    -1.0
                } else if x < 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
            Gripper::ThresholdHalfInvert => {
                if g < 0.5 {
                    1.0
                } else {
                    -1.0
                }
            }
        }
    }
}

/// The part of a chunk longer than `replan_steps` that a model's own loop executes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChunkEnd {
    First,
    Last,
}

/// A model's observation and action conventions.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// `--model-profile` name.
    pub name: &'static str,
    /// The model and the script the profile follows.
    pub source: &'static str,
    /// The wire format its server speaks.
    pub format: Format,
    pub orientation: Orientation,
    /// Side of the square images sent (`None`: as rendered).
    pub image_size: Option<u32>,
    pub state: StateLayout,
    pub instruction: Instruction,
    /// Actions used from each chunk before asking again (0: the whole chunk).
    pub replan_steps: usize,
    /// Which `replan_steps` of a longer chunk are used: the first, or the last (OpenVLA-OFT's
    /// loop extends a `deque(maxlen=replan)`, which keeps a longer chunk's tail).
    pub chunk_end: ChunkEnd,
    pub gripper: Gripper,
    /// The adapter keeps per-episode state (action ensembling, reasoning sessions): the first
    /// request of each episode carries `reset: true`.
    pub session: bool,
    /// The server un-normalises actions with one suite's statistics, chosen at its start
    /// (OpenVLA-OFT's `--unnorm_key`, InstructVLA's `{suite}_no_noops`): one server per suite.
    pub one_suite_per_server: bool,
}

/// Every profile, in the README's order.
pub const PROFILES: [Profile; 7] = [
    // openpi `examples/libero/main.py`: 224² resize_with_pad, chunk 10, replan 5.
    Profile {
        name: "pi05",
        source: "pi0.5, openpi examples/libero/main.py",
        format: Format::Openpi,
        orientation: Orientation::Rotated180,
        image_size: Some(224),
        state: StateLayout::Eef8,
        instruction: Instruction::Verbatim,
        replan_steps: 5,
        chunk_end: ChunkEnd::First,
        gripper: Gripper::AsIs,
        session: false,
        one_suite_per_server: false,
    },
    // openvla-oft `run_libero_eval.py` + `vla-scripts/deploy.py`: the server resizes 256² frames
    // with the same `resize_image_for_policy` (JPEG, lanczos3) the eval script calls, builds
    // the prompt and center-crops; chunk 8, all executed open loop.
    Profile {
        name: "openvla-oft",
        source: "OpenVLA-OFT, moojink/openvla-oft experiments/robot/libero/run_libero_eval.py",
        format: Format::OpenVlaOft,
        orientation: Orientation::Rotated180,
        image_size: None,
        state: StateLayout::Eef8,
        instruction: Instruction::Verbatim,
        replan_steps: 8,
        chunk_end: ChunkEnd::Last,
        gripper: Gripper::OpenVlaBinarizeInvert,
        session: false,
        one_suite_per_server: true,
    },
    // InternVLA-A1.5 `evaluation/LIBERO/model2libero_interface.py`: 256² rotated frames,
    // float32 state, replan 8, gripper thresholded at 0.5 and flipped.
    Profile {
        name: "internvla",
        source: "InternVLA-A1.5, evaluation/LIBERO/model2libero_interface.py",
        format: Format::InternVla,
        orientation: Orientation::Rotated180,
        image_size: None,
        state: StateLayout::Eef8,
        instruction: Instruction::Verbatim,
        replan_steps: 8,
        chunk_end: ChunkEnd::First,
        gripper: Gripper::ThresholdHalfInvert,
        session: false,
        one_suite_per_server: false,
    },
    // Xiaomi-Robotics-0 `eval_libero/main.py`: 256² rotated PIL images, state padded to 32,
    // "Capitalized." instruction, replan 10, actions used as returned.
    Profile {
        name: "xiaomi",
        source: "Xiaomi-Robotics-0, eval_libero/main.py",
        format: Format::Xiaomi,
        orientation: Orientation::Rotated180,
        image_size: None,
        state: StateLayout::Eef8Padded(32),
        instruction: Instruction::CapitalizedSentence,
        replan_steps: 10,
        chunk_end: ChunkEnd::First,
        gripper: Gripper::AsIs,
        session: false,
        one_suite_per_server: false,
    },
    // MolmoAct2 through LeRobot's async inference. lerobot-eval's `LiberoProcessorStep` (an env
    // processor, which the async server does not run) flips frames in H and W and builds the 8-D
    // state, so the client does both; chunk 10 (`action_horizon=10` for the LIBERO mixture),
    // actions in LIBERO's convention. The render size is the eval config's (LeRobot's default
    // differs between versions); we send frames as rendered (`--size`).
    Profile {
        name: "molmoact2",
        source: "MolmoAct2, allenai/molmoact2 vendored LeRobot (async inference)",
        format: Format::LeRobot,
        orientation: Orientation::Rotated180,
        image_size: None,
        state: StateLayout::Eef8,
        instruction: Instruction::Verbatim,
        replan_steps: 10,
        chunk_end: ChunkEnd::First,
        gripper: Gripper::AsIs,
        session: false,
        one_suite_per_server: false,
    },
    // InstructVLA `deploy/libero/run_libero_eval.py`: one action per step (the model ensembles
    // its own chunks across steps, reset per episode), OpenVLA gripper convention. Our adapter
    // `serving/instructvla_server.py` runs the repository's own image helpers on raw frames.
    Profile {
        name: "instructvla",
        source: "InstructVLA, deploy/libero/run_libero_eval.py (adapter serving/instructvla_server.py)",
        format: Format::Openpi,
        orientation: Orientation::Robosuite,
        image_size: None,
        state: StateLayout::Eef8,
        instruction: Instruction::Verbatim,
        replan_steps: 1,
        chunk_end: ChunkEnd::First,
        gripper: Gripper::OpenVlaBinarizeInvert,
        session: true,
        one_suite_per_server: true,
    },
    // Action-Sketcher `run_libero_example.py`: pi0 on LeRobot at 224², the whole chunk executed
    // (the adapter `serving/action_sketcher_server.py` runs the reasoning turns, denormalises and
    // returns the chunk); replan 0 means "use the whole chunk, then ask again".
    Profile {
        name: "action-sketcher",
        source: "Action-Sketcher, FlagOpen/Action-Sketcher run_libero_example.py (adapter serving/action_sketcher_server.py)",
        format: Format::Openpi,
        orientation: Orientation::Robosuite,
        image_size: Some(224),
        state: StateLayout::Eef8,
        instruction: Instruction::Verbatim,
        replan_steps: 0,
        chunk_end: ChunkEnd::First,
        gripper: Gripper::AsIs,
        session: true,
        one_suite_per_server: false,
    },
];

impl Profile {
    /// The profile named `name`.
    pub fn named(name: &str) -> Option<&'static Profile> {
        PROFILES.iter().find(|p| p.name == name)
    }

    /// Names of every profile, for messages.
    pub fn names() -> Vec<&'static str> {
        PROFILES.iter().map(|p| p.name).collect()
    }

    /// How many actions of a chunk of `len` rows to use: `replan_steps`, or the whole chunk
    /// when it is 0.
    pub fn used(&self, len: usize) -> usize {
        if self.replan_steps == 0 { len } else { self.replan_steps }
    }

    /// The rows of `chunk` to execute ([`Profile::used`] of them, from its [`ChunkEnd`]);
    /// `None` where the chunk is shorter.
    pub fn executed<'c>(&self, chunk: &'c [[f64; 7]]) -> Option<&'c [[f64; 7]]> {
        let n = self.used(chunk.len());
        let skip = chunk.len().checked_sub(n)?;
        Some(match self.chunk_end {
            ChunkEnd::First => &chunk[..n],
            ChunkEnd::Last => &chunk[skip..],
        })
    }

    /// One camera frame as the model receives it.
    pub fn image(&self, upright: &RgbImage) -> RgbImage {
        let oriented = match self.orientation {
            Orientation::Rotated180 => mirror_left_right(upright),
            Orientation::Robosuite => flip_rows(upright),
        };
        match self.image_size {
            Some(side) => resize_with_pad(&oriented, side, side),
            None => oriented,
        }
    }

    pub fn state(&self, obs: &Observation) -> Vec<f64> {
        let mut s = obs.state8().to_vec();
        if let StateLayout::Eef8Padded(n) = self.state {
            s.resize(n.max(8), 0.0);
        }
        s
    }

    pub fn instruction(&self, task: &str) -> String {
        match self.instruction {
            Instruction::Verbatim => task.to_string(),
            Instruction::CapitalizedSentence => format!("{}.", capitalize(task)),
        }
    }
}

/// Python's `str.capitalize()`: first character upper case, the rest lower case.
pub fn capitalize(s: &str) -> String {
    let mut chars = s.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars.flat_map(char::to_lowercase)).collect(),
        None => String::new(),
    }
}

/// robosuite's bottom-up row order.
pub fn flip_rows(img: &RgbImage) -> RgbImage {
    let row = img.width as usize * 3;
    let data = img.data.chunks_exact(row).rev().flatten().copied().collect();
    RgbImage { width: img.width, height: img.height, data }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_of_the_papers_table_has_its_profile() {
        let paper: Vec<&str> = crate::report::paper::TABLE1.iter().map(|p| p.profile).collect();
        assert_eq!(paper.len(), PROFILES.len());
        for profile in paper {
            assert!(Profile::named(profile).is_some(), "{profile}");
        }
    }

    #[test]
    fn grippers_follow_each_script() {
        let oft: Vec<f64> =
            [0.0, 0.3, 0.5, 0.9, 1.0].iter().map(|&g| Gripper::OpenVlaBinarizeInvert.apply(g)).collect();
        assert_eq!(oft, [1.0, 1.0, 0.0, -1.0, -1.0]);
        let intern: Vec<f64> = [0.0, 0.49, 0.5, 1.0].iter().map(|&g| Gripper::ThresholdHalfInvert.apply(g)).collect();
        assert_eq!(intern, [1.0, 1.0, -1.0, -1.0]);
        assert_eq!(Gripper::AsIs.apply(-0.3), -0.3);
    }

    #[test]
    fn instructions_and_names() {
        assert_eq!(capitalize("put both moka pots on the stove"), "Put both moka pots on the stove");
        assert_eq!(capitalize("pick up the BBQ sauce"), "Pick up the bbq sauce");
        let x = Profile::named("xiaomi").unwrap();
        assert_eq!(x.instruction("open the drawer"), "Open the drawer.");
        assert_eq!(Profile::names().len(), 7);
        assert!(Profile::named("gpt").is_none());
    }

    #[test]
    fn images_are_oriented_and_sized() {
        let img = RgbImage::from_raw(2, 2, vec![1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4]).unwrap();
        assert_eq!(flip_rows(&img).data, [3, 3, 3, 4, 4, 4, 1, 1, 1, 2, 2, 2]);
        let pi = Profile::named("pi05").unwrap();
        let big = RgbImage::filled(256, 256, [9, 9, 9]).unwrap();
        assert_eq!((pi.image(&big).width, pi.image(&big).height), (224, 224));
        assert_eq!(Profile::named("xiaomi").unwrap().image(&big).width, 256);
    }
}
