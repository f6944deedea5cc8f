//! The report's clips: the first episode of each cue family, filmed while it ran
//! ([`crate::env::film`]), shown by `clips.md` in the report folder, so people see what ran.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

use vifo_cues::Family;

use super::family_of;
use crate::env::film::Filming;
use crate::spec::{EpisodeRecord, EpisodeSpec, Outcome};
use crate::studies;

/// The clips' folder inside the report folder.
pub const FOLDER: &str = "clips";

/// The first episode of each cue family in `specs`, in their order: an episode of the main
/// benchmark's suites whose cue is drawn over the frames (what Table 2 counts).
pub fn first_episodes(specs: &[EpisodeSpec]) -> BTreeMap<Family, &EpisodeSpec> {
    let mut out = BTreeMap::new();
    for spec in specs.iter().filter(|s| s.cue_form.is_overlay() && !studies::own_suite(s)) {
        if let Some(family) = spec.instance.as_deref().and_then(family_of) {
            out.entry(family).or_insert(spec);
        }
    }
    out
}

/// Where a policy's clip of a family goes, relative to the report folder; `policy_dir` is the
/// policy's name as a file name.
pub fn clip_path(policy_dir: &str, family: Family) -> PathBuf {
    Path::new(FOLDER).join(policy_dir).join(format!("{family}.gif"))
}

/// Films the first episode of each family of `specs` into `report_dir` (`size`² per camera,
/// every `every`th step).
pub fn filming(specs: &[EpisodeSpec], report_dir: &Path, policy_dir: &str, size: u32, every: usize) -> Filming {
    let clips = first_episodes(specs)
        .into_iter()
        .map(|(family, spec)| (spec.key(), report_dir.join(clip_path(policy_dir, family))))
        .collect();
    Filming { clips, size, every }
}

/// How an episode ended, under its clip: a clip alone does not say whether the robot did the
/// task, nor that the episode ended in an error.
fn outcome(record: Option<&EpisodeRecord>) -> String {
    let done = |task: &str, success: Option<bool>| success.map(|s| format!("{task} {}", if s { "done" } else { "not done" }));
    match record.map(|r| &r.outcome) {
        None => "no record".to_string(),
        Some(Outcome::Error { message }) => {
            let short: String = message.chars().take(80).collect();
            format!("error: {}{}", short.replace('|', "\\|"), if short.len() < message.len() { "…" } else { "" })
        }
        Some(Outcome::Completed { language_success, cue_success, steps }) => {
            let tasks: Vec<String> = [done("language task", *language_success), done("cue task", *cue_success)].into_iter().flatten().collect();
            format!("{}, {steps} steps", tasks.join(", "))
        }
    }
}

/// Writes `clips.md` into `report_dir`, showing the clips of `policies` (name, name as a file
/// name) found there for the first episodes of `specs`, drawn with the look named `look`, each
/// with how its episode ended in `records` (the last record of the policy and episode);
/// returns its Markdown, empty (and writes nothing) when there is no clip.
pub fn write(
    report_dir: &Path,
    specs: &[EpisodeSpec],
    policies: &[(String, String)],
    look: &str,
    records: &[EpisodeRecord],
) -> std::io::Result<String> {
    let last: BTreeMap<(&str, String), &EpisodeRecord> = records.iter().map(|r| ((r.policy.as_str(), r.spec.key()), r)).collect();
    let firsts = first_episodes(specs);
    let found: Vec<(Family, &EpisodeSpec, Vec<Option<PathBuf>>)> = firsts
        .into_iter()
        .map(|(family, spec)| {
            let clips = policies
                .iter()
                .map(|(_, dir)| Some(clip_path(dir, family)).filter(|p| report_dir.join(p).is_file()))
                .collect();
            (family, spec, clips)
        })
        .collect();
    if found.iter().all(|(_, _, clips)| clips.iter().all(Option::is_none)) {
        return Ok(String::new());
    }
    let mut md = String::from("### The first episode of each cue family\n\n");
    md += "Agentview with the cue as the policy saw it (left) and the wrist camera (right), played in real time.\n\n";
    // The tables may say "none" where the policies read the simulator; the clips are drawn all the same.
    let _ = writeln!(md, "Drawn with look: {look}.\n");
    md += "| family | episode |";
    for (name, _) in policies {
        let _ = write!(md, " {name} |");
    }
    md += "\n|---|---|";
    md += &"---|".repeat(policies.len());
    md += "\n";
    for (family, spec, clips) in &found {
        let _ = write!(md, "| {family} | {} {} `{}` |", spec.task, spec.protocol.name(), spec.instance.as_deref().unwrap_or("-"));
        for ((name, _), clip) in policies.iter().zip(clips) {
            match clip {
                // Markdown links use forward slashes on every platform.
                Some(p) => {
                    let link: Vec<String> = p.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
                    let ended = outcome(last.get(&(name.as_str(), spec.key())).copied());
                    let _ = write!(md, " ![{family}]({})<br>{ended} |", link.join("/"));
                }
                None => md += " (no clip) |",
            }
        }
        md += "\n";
    }
    crate::runner::create_dir(report_dir)?;
    std::fs::write(report_dir.join("clips.md"), &md)?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::benchmark::specs::spec;
    use crate::spec::{Protocol, TaskRef};

    fn specs() -> Vec<EpisodeSpec> {
        let goal = TaskRef { suite: "libero_goal".into(), index: 0 };
        vec![
            spec(&goal, Protocol::Original, None, 0, 0).unwrap(),
            spec(&goal, Protocol::Conflict, Some("libero_goal/0/F1/caption_bar"), 0, 0).unwrap(),
            spec(&goal, Protocol::Authorized, Some("libero_goal/0/F1/caption_bar"), 0, 0).unwrap(),
            spec(&goal, Protocol::Authorized, Some("libero_goal/0/F2/bounding_boxes"), 0, 0).unwrap(),
        ]
    }

    #[test]
    fn the_first_episode_of_each_family_in_order() {
        let specs = specs();
        let firsts = first_episodes(&specs);
        assert_eq!(firsts.keys().copied().collect::<Vec<_>>(), [Family::F1, Family::F2]);
        assert_eq!(firsts[&Family::F1].protocol, Protocol::Conflict);
        let filming = filming(&specs, Path::new("r"), "p", 64, 3);
        assert_eq!(filming.clips[&specs[1].key()], Path::new("r/clips/p/F1.gif"));
        assert_eq!((filming.clips.len(), filming.size, filming.every), (2, 64, 3));
    }

    #[test]
    fn clips_md_links_the_clips_found() {
        let dir = tempfile::tempdir().unwrap();
        let policies = [("ws://h:1".to_string(), "ws___h_1".to_string())];
        assert_eq!(write(dir.path(), &specs(), &policies, "built-in", &[]).unwrap(), "", "no clip, no section");
        assert!(!dir.path().join("clips.md").exists());
        let clip = dir.path().join(clip_path("ws___h_1", Family::F2));
        std::fs::create_dir_all(clip.parent().unwrap()).unwrap();
        std::fs::write(&clip, b"GIF89a").unwrap();
        let md = write(dir.path(), &specs(), &policies, "libero-assets:0123", &[]).unwrap();
        assert!(md.contains("Drawn with look: libero-assets:0123.\n"), "{md}");
        assert!(md.contains("| F2 | libero_goal/0 authorized `libero_goal/0/F2/bounding_boxes` | ![F2](clips/ws___h_1/F2.gif)<br>no record |"), "{md}");
        assert!(md.contains("| F1 | libero_goal/0 conflict `libero_goal/0/F1/caption_bar` | (no clip) |"), "{md}");
        assert_eq!(std::fs::read_to_string(dir.path().join("clips.md")).unwrap(), md);
        // Under each clip, how its episode ended (the last record of it).
        let record = |outcome| EpisodeRecord {
            version: crate::spec::RESULTS_VERSION,
            spec: specs()[3].clone(),
            policy: "ws://h:1".into(),
            outcome,
            wall_ms: 0.0,
            set: vifo_cues::SetName::Paper,
            look: String::new(),
        };
        let failed = record(Outcome::Error { message: "policy connection: reset | by peer".into() });
        let done = record(Outcome::Completed { language_success: None, cue_success: Some(true), steps: 88 });
        let md = write(dir.path(), &specs(), &policies, "built-in", std::slice::from_ref(&failed)).unwrap();
        assert!(md.contains("F2.gif)<br>error: policy connection: reset \\| by peer |"), "{md}");
        let md = write(dir.path(), &specs(), &policies, "built-in", &[failed, done]).unwrap();
        assert!(md.contains("F2.gif)<br>cue task done, 88 steps |"), "{md}");
    }
}
