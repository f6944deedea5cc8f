//! The exported question set and prediction files.
//!
//! Layout of an export folder: `questions.jsonl` (one [`Question`] per line) and
//! `images/<instance id with / as ->.png` (one RGB PNG per instance, shared by its four
//! questions). Predictions are JSONL lines `{"id", "prediction"}` with the model's raw text.

use std::collections::BTreeMap;
use std::fs::OpenOptions;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;

use serde::de::DeserializeOwned;
use vifo_cues::RgbImage;

use super::{Prediction, Question, VqaError};

/// The questions file inside an export folder.
pub const QUESTIONS_FILE: &str = "questions.jsonl";

/// Writes `dir/questions.jsonl` and one PNG per instance; `render` gives the (cue-inserted)
/// observation of an instance id. Returns the number of images written. The questions file is
/// removed first and written last, so an export stopped half way over an earlier one is no
/// export (scoring refuses it) rather than old questions over a mix of old and new images.
pub fn export<F>(dir: &Path, questions: &[Question], mut render: F) -> Result<usize, VqaError>
where
    F: FnMut(&str) -> Result<RgbImage, String>,
{
    std::fs::create_dir_all(dir.join("images")).map_err(|e| VqaError::io(dir, e))?;
    let questions_path = dir.join(QUESTIONS_FILE);
    match std::fs::remove_file(&questions_path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(VqaError::io(&questions_path, e)),
        _ => {}
    }
    let mut written = std::collections::BTreeSet::new();
    for q in questions {
        if !written.insert(q.instance_id.clone()) {
            continue;
        }
        let img =
            render(&q.instance_id).map_err(|message| VqaError::Image { instance: q.instance_id.clone(), message })?;
        let path = dir.join(&q.image);
        let buffer = image::RgbImage::from_raw(img.width, img.height, img.data).ok_or_else(|| VqaError::Image {
            instance: q.instance_id.clone(),
            message: "pixel buffer does not match its width and height".into(),
        })?;
        buffer.save_with_format(&path, image::ImageFormat::Png).map_err(|e| VqaError::Image {
            instance: q.instance_id.clone(),
            message: format!("writing {}: {e}", path.display()),
        })?;
    }
    let mut text = String::new();
    for q in questions {
        text.push_str(&serde_json::to_string(q).map_err(|e| VqaError::Client(e.to_string()))?);
        text.push('\n');
    }
    std::fs::write(&questions_path, text).map_err(|e| VqaError::io(&questions_path, e))?;
    Ok(written.len())
}

/// Reads `questions.jsonl` (a folder is taken to hold one) and checks each question's shape.
pub fn read_questions(path: &Path) -> Result<Vec<Question>, VqaError> {
    let path = if path.is_dir() { path.join(QUESTIONS_FILE) } else { path.to_path_buf() };
    if !path.exists() {
        return Err(VqaError::NoQuestions(path));
    }
    let (questions, _): (Vec<Question>, _) = read_jsonl(&path, "a question object", false)?;
    if questions.is_empty() {
        return Err(VqaError::EmptyQuestions(path));
    }
    // A repeated id or stage of an instance (a merged or hand-edited file) would count twice
    // in its stage and break the instance's full chain.
    let (mut ids, mut stages) = (std::collections::BTreeSet::new(), std::collections::BTreeSet::new());
    for (i, q) in questions.iter().enumerate() {
        let bad = |message: String| VqaError::BadLine { path: path.clone(), line: i + 1, message };
        if !ids.insert(q.id.as_str()) {
            return Err(bad(format!("question {} appears twice", q.id)));
        }
        if !stages.insert((q.instance_id.as_str(), q.stage)) {
            return Err(bad(format!("question {} asks the {} stage of {} again", q.id, q.stage.name(), q.instance_id)));
        }
        // The id names the family (`<suite>/<task>/<family>/<variant>`); a `family` field
        // that says otherwise would move the question to another family's column.
        if q.instance_id.split('/').nth(2) != Some(q.family.to_string().as_str()) {
            return Err(bad(format!("question {} is of family {}, but its instance {} is not", q.id, q.family, q.instance_id)));
        }
        if q.options.len() != 4 {
            return Err(bad(format!("question {} has {} options, expected 4", q.id, q.options.len())));
        }
        if !["A", "B", "C", "D"].contains(&q.answer.as_str()) {
            return Err(bad(format!("question {} has answer {:?}, expected a letter A-D", q.id, q.answer)));
        }
    }
    Ok(questions)
}

/// Reads a predictions file into id → raw text (a later line for the same id wins). An
/// unterminated last line that does not parse is taken as cut off and ignored; its length
/// is returned.
pub fn read_predictions(path: &Path) -> Result<(BTreeMap<String, String>, usize), VqaError> {
    let (lines, cut): (Vec<Prediction>, usize) = read_jsonl(path, "{\"id\", \"prediction\"}", true)?;
    Ok((lines.into_iter().map(|p| (p.id, p.prediction)).collect(), cut))
}

/// Reads a predictions file to be appended to (`vqa answer` resuming): a cut-off last line is
/// removed and a complete one without its newline gets one, so the next line starts clean
/// instead of being glued to it (which would corrupt the file for every later reader).
pub fn resume_predictions(path: &Path) -> Result<BTreeMap<String, String>, VqaError> {
    let (map, cut) = read_predictions(path)?;
    let len = std::fs::metadata(path).map_err(|e| VqaError::io(path, e))?.len();
    let mut file = OpenOptions::new().read(true).write(true).open(path).map_err(|e| VqaError::io(path, e))?;
    if cut > 0 {
        file.set_len(len - cut as u64).map_err(|e| VqaError::io(path, e))?;
    } else if len > 0 {
        let mut last = [0u8];
        file.seek(SeekFrom::End(-1)).and_then(|_| file.read_exact(&mut last)).map_err(|e| VqaError::io(path, e))?;
        if last[0] != b'\n' {
            file.seek(SeekFrom::End(0)).and_then(|_| file.write_all(b"\n")).map_err(|e| VqaError::io(path, e))?;
        }
    }
    Ok(map)
}

/// Appends predictions, one line per write (safe to stop at any time).
pub fn append_predictions(path: &Path, predictions: &[Prediction]) -> Result<(), VqaError> {
    let mut file = OpenOptions::new().create(true).append(true).open(path).map_err(|e| VqaError::io(path, e))?;
    for p in predictions {
        let mut line = serde_json::to_vec(p).map_err(|e| VqaError::Client(e.to_string()))?;
        line.push(b'\n');
        file.write_all(&line).map_err(|e| VqaError::io(path, e))?;
    }
    Ok(())
}

/// JSONL reader: every line must parse, except (with `tolerate_cut`) an unterminated last line.
fn read_jsonl<T: DeserializeOwned>(path: &Path, what: &str, tolerate_cut: bool) -> Result<(Vec<T>, usize), VqaError> {
    let text = crate::text_file::read(path).map_err(|e| VqaError::io(path, e))?;
    let terminated = text.ends_with('\n');
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::with_capacity(lines.len());
    for (i, line) in lines.iter().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        match serde_json::from_str(line) {
            Ok(v) => out.push(v),
            Err(_) if tolerate_cut && !terminated && i + 1 == lines.len() => return Ok((out, line.len())),
            Err(e) => {
                return Err(VqaError::BadLine {
                    path: path.to_path_buf(),
                    line: i + 1,
                    message: format!("expected {what}: {e}"),
                });
            }
        }
    }
    Ok((out, 0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prediction_files_tolerate_only_a_cut_last_line() {
        let dir = std::env::temp_dir().join(format!("vifo-vqa-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.jsonl");
        let p = |id: &str, t: &str| Prediction { id: id.into(), prediction: t.into() };
        append_predictions(&path, &[p("a", "B"), p("b", "C"), p("a", "D")]).unwrap();
        let mut text = std::fs::read_to_string(&path).unwrap();
        text.push_str("{\"id\": \"c\", \"predic");
        std::fs::write(&path, &text).unwrap();
        let (map, cut) = read_predictions(&path).unwrap();
        assert_eq!((map["a"].as_str(), map["b"].as_str(), map.len(), cut), ("D", "C", 2, 19));
        // A complete last line without a newline is kept.
        std::fs::write(&path, "{\"id\": \"x\", \"prediction\": \"A\"}").unwrap();
        assert_eq!(read_predictions(&path).unwrap().0.len(), 1);
        // A bad line in the middle is an error with its position.
        std::fs::write(&path, "{\"id\": \"x\", \"prediction\": \"A\"}\n[1]\n{\"id\": \"y\", \"prediction\": \"A\"}\n")
            .unwrap();
        let err = read_predictions(&path).unwrap_err().to_string();
        assert!(err.contains("p.jsonl:2:") && err.contains("\"prediction\""), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_resumed_predictions_file_takes_new_lines_after_a_cut_or_unterminated_last_line() {
        let dir = std::env::temp_dir().join(format!("vifo-vqa-resume-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.jsonl");
        let a = "{\"id\":\"a\",\"prediction\":\"B\"}";
        let c = Prediction { id: "c".into(), prediction: "D".into() };
        for (before, kept) in [(format!("{a}\n{{\"id\":\"b\",\"pre"), 1), (a.to_string(), 1), (format!("{a}\n"), 1), (String::new(), 0)] {
            std::fs::write(&path, &before).unwrap();
            assert_eq!(resume_predictions(&path).unwrap().len(), kept, "{before:?}");
            append_predictions(&path, std::slice::from_ref(&c)).unwrap();
            let (map, cut) = read_predictions(&path).unwrap();
            assert_eq!((map.len(), map["c"].as_str(), cut), (kept + 1, "D", 0), "{before:?}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_folder_without_questions_says_which_command_writes_them() {
        let dir = std::env::temp_dir().join(format!("vifo-vqa-noquestions-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let err = read_questions(&dir).unwrap_err().to_string();
        assert!(err.contains("questions.jsonl: no such file") && err.contains("vifo vqa export"), "{err}");
        // An empty file is no export either (the oracle and the blind baselines answered nothing).
        std::fs::write(dir.join(QUESTIONS_FILE), "\n").unwrap();
        let err = read_questions(&dir).unwrap_err().to_string();
        assert!(err.contains("questions.jsonl holds no questions"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// An export stopped half way over an earlier one leaves no questions file: the old
    /// questions would have been scored against a mix of old and new images.
    #[test]
    fn an_export_stopped_half_way_is_no_export() {
        let dir = tempfile::tempdir().unwrap();
        let question = |instance: &str| -> Question {
            serde_json::from_str(&format!(r#"{{"id":"{instance}/detection","instance_id":"{instance}","family":"F1","stage":"detection","image":"images/{}.png","question":"q","options":["a","b","c","d"],"answer":"A"}}"#, instance.replace('/', "_"))).unwrap()
        };
        let questions = [question("t/0/F1/a"), question("t/0/F1/b")];
        let image = || RgbImage { width: 2, height: 2, data: vec![9; 12] };
        export(dir.path(), &questions, |_| Ok(image())).unwrap();
        assert_eq!(read_questions(dir.path()).unwrap().len(), 2);
        let mut calls = 0;
        let stopped = export(dir.path(), &questions, |_| {
            calls += 1;
            if calls == 2 { Err("stopped".into()) } else { Ok(image()) }
        });
        assert!(stopped.is_err());
        assert!(matches!(read_questions(dir.path()), Err(VqaError::NoQuestions(_))));
    }

    #[test]
    fn a_question_file_that_repeats_an_id_or_stage_is_refused() {
        let dir = std::env::temp_dir().join(format!("vifo-vqa-repeats-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let line = |id: &str, stage: &str| {
            format!(r#"{{"id":"{id}","instance_id":"t/0/F1/v","family":"F1","stage":"{stage}","image":"x.png","question":"q","options":["a","b","c","d"],"answer":"A"}}"#)
        };
        for (lines, says) in [
            ([line("t/0/F1/v/detection", "detection"), line("t/0/F1/v/detection", "detection")], "questions.jsonl:2: question t/0/F1/v/detection appears twice"),
            ([line("t/0/F1/v/detection", "detection"), line("t/0/F1/v/other", "detection")], "asks the detection stage of t/0/F1/v again"),
            ([line("t/0/F1/v/detection", "detection"), line("t/0/F1/v/semantic", "semantic").replace(r#""family":"F1""#, r#""family":"F5""#)],
                "questions.jsonl:2: question t/0/F1/v/semantic is of family F5, but its instance t/0/F1/v is not"),
        ] {
            std::fs::write(dir.join(QUESTIONS_FILE), lines.join("\n") + "\n").unwrap();
            let err = read_questions(&dir).unwrap_err().to_string();
            assert!(err.contains(says), "{err}");
        }
        std::fs::write(dir.join(QUESTIONS_FILE), line("t/0/F1/v/detection", "detection") + "\n" + &line("t/0/F1/v/semantic", "semantic")).unwrap();
        assert_eq!(read_questions(&dir).unwrap().len(), 2);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
