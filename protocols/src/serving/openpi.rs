//! openpi's protocol ([`crate::remote`]) carrying a profile's observation: the same keys as
//! openpi's LIBERO client (`observation/image`, `observation/wrist_image` `|u1` H×W×3,
//! `observation/state` `<f8`, `prompt`), plus `reset: true|false` for adapters that keep an
//! episode session (InstructVLA, Action-Sketcher). With the `pi05` profile the request is
//! byte for byte what [`crate::remote::encode_request`] sends.

use rmpv::Value;

use super::{ModelInput, ServingConfig, Transport};
use crate::policy::{Policy, PolicyError};
use crate::remote::{RemoteConfig, RemotePolicy, ndarray, parse_reply};

pub struct OpenpiTransport {
    remote: RemotePolicy,
    session: bool,
}

impl OpenpiTransport {
    pub fn connect(config: &ServingConfig) -> Result<OpenpiTransport, PolicyError> {
        let remote = RemotePolicy::with_config(RemoteConfig {
            connect_timeout: config.connect_timeout,
            request_timeout: config.request_timeout,
            ..RemoteConfig::new(&config.url)
        })?;
        Ok(OpenpiTransport { remote, session: config.profile.session })
    }
}

/// The msgpack request.
pub fn encode(input: &ModelInput, session: bool) -> Result<Vec<u8>, PolicyError> {
    let mut entries = Vec::with_capacity(5);
    for (key, img) in [("observation/image", &input.image), ("observation/wrist_image", &input.wrist)] {
        let shape = [img.height as usize, img.width as usize, 3];
        entries.push((Value::from(key), ndarray::encode_u8(&shape, img.data.clone())));
    }
    entries.push((Value::from("observation/state"), ndarray::encode_f64(&[input.state.len()], &input.state)));
    entries.push((Value::from("prompt"), Value::from(input.instruction.as_str())));
    if session {
        entries.push((Value::from("reset"), Value::Boolean(input.episode_start)));
    }
    let mut bytes = Vec::new();
    rmpv::encode::write_value(&mut bytes, &Value::Map(entries))
        .map_err(|e| PolicyError::Other(format!("encoding the request: {e}")))?;
    Ok(bytes)
}

impl Transport for OpenpiTransport {
    fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
        let request = encode(input, self.session)?;
        Ok(self.remote.round_trip(&request, parse_reply)?.actions)
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        self.remote.reset()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::policy::Observation;
    use crate::serving::Profile;
    use vifo_cues::RgbImage;

    #[test]
    fn pi05_requests_are_openpis() {
        let frame = |salt: u8| {
            RgbImage::from_raw(256, 256, (0..256 * 256 * 3).map(|i| (i as u8).wrapping_mul(salt)).collect()).unwrap()
        };
        let obs = Observation {
            agentview: frame(3),
            wrist: frame(7),
            eef_pos: [0.1, 0.2, 0.9],
            eef_quat_xyzw: [0.9, 0.1, 0.2, 0.3],
            gripper_qpos: [0.04, -0.04],
            joint_pos: [0.0; 7],
            instruction: "open the top drawer".into(),
            step: 3,
        };
        let input = ModelInput::new(Profile::named("pi05").unwrap(), &obs, true).unwrap();
        assert_eq!(encode(&input, false).unwrap(), crate::remote::encode_request(&obs, 224).unwrap());
    }
}
