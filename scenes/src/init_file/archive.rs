//! Finds the pickle inside a `torch.save` zip archive.

use std::io::{Cursor, Read};

/// The largest pickle we accept; LIBERO's are about 20–60 KB.
const MAX_PICKLE_BYTES: u64 = 256 << 20;

/// The bytes of the archive's `<name>/data.pkl` entry.
pub fn data_pickle(bytes: &[u8]) -> Result<Vec<u8>, String> {
    if bytes.first() == Some(&0x80) {
        return Err("this is a bare pickle (the legacy, pre-1.6 torch.save format), not a zip archive".into());
    }
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| format!("not a torch zip archive: {e}"))?;
    let name = zip
        .file_names()
        .find(|n| *n == "data.pkl" || n.ends_with("/data.pkl"))
        .map(str::to_string)
        .ok_or_else(|| {
            let names: Vec<&str> = zip.file_names().collect();
            format!("the archive has no data.pkl entry (entries: {})", names.join(", "))
        })?;
    let entry = zip.by_name(&name).map_err(|e| format!("cannot open {name}: {e}"))?;
    let mut pickle = Vec::new();
    entry
        .take(MAX_PICKLE_BYTES + 1)
        .read_to_end(&mut pickle)
        .map_err(|e| format!("cannot read {name}: {e}"))?;
    if pickle.len() as u64 > MAX_PICKLE_BYTES {
        return Err(format!("{name} is larger than {MAX_PICKLE_BYTES} bytes"));
    }
    Ok(pickle)
}
