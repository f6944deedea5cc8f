//! msgpack-numpy exactly as `openpi_client.msgpack_numpy` writes and reads it.
//!
//! An array is a map whose four keys are msgpack **bin** (not str) values: `__ndarray__`
//! (true), `data` (C-order bytes), `dtype` (numpy's `dtype.str`, e.g. `|u1`, `<f8`) and
//! `shape` (array of ints). Python only recognises the map with bin keys; we accept str keys
//! too when reading, since other servers may write them.

use rmpv::Value;

/// An array in its wire form.
#[derive(Clone, Debug, PartialEq)]
pub struct NdArray {
    pub dtype: String,
    pub shape: Vec<usize>,
    pub data: Vec<u8>,
}

fn bin_key(k: &str) -> Value {
    Value::Binary(k.as_bytes().to_vec())
}

/// The wire map of an array, keys in the order Python writes them.
pub fn encode(dtype: &str, shape: &[usize], data: Vec<u8>) -> Value {
    Value::Map(vec![
        (bin_key("__ndarray__"), Value::Boolean(true)),
        (bin_key("data"), Value::Binary(data)),
        (bin_key("dtype"), Value::String(dtype.into())),
        (bin_key("shape"), Value::Array(shape.iter().map(|&n| Value::from(n as u64)).collect())),
    ])
}

/// A `uint8` array (`|u1`).
pub fn encode_u8(shape: &[usize], data: Vec<u8>) -> Value {
    encode("|u1", shape, data)
}

/// A little-endian `float64` array (`<f8`).
pub fn encode_f64(shape: &[usize], values: &[f64]) -> Value {
    encode("<f8", shape, values.iter().flat_map(|v| v.to_le_bytes()).collect())
}

/// The value under `key` in a msgpack map, whether the key is str or bin.
pub fn get<'a>(map: &'a [(Value, Value)], key: &str) -> Option<&'a Value> {
    map.iter().find(|(k, _)| key_bytes(k) == Some(key.as_bytes())).map(|(_, v)| v)
}

/// The bytes of a str or bin key.
pub fn key_bytes(k: &Value) -> Option<&[u8]> {
    match k {
        Value::String(s) => Some(s.as_bytes()),
        Value::Binary(b) => Some(b),
        _ => None,
    }
}

/// Reads an array map. `Ok(None)` when `v` is not an array at all; `Err` names what is wrong
/// with one that claims to be.
pub fn decode(v: &Value) -> Result<Option<NdArray>, String> {
    let Value::Map(map) = v else { return Ok(None) };
    if get(map, "__ndarray__").is_none() {
        return Ok(None);
    }
    let data = match get(map, "data") {
        Some(Value::Binary(b)) => b.clone(),
        Some(other) => return Err(format!("array `data` must be bytes, found {}", kind(other))),
        None => return Err("array without `data`".into()),
    };
    let dtype = match get(map, "dtype") {
        Some(Value::String(s)) => s.as_str().ok_or("array `dtype` is not valid UTF-8")?.to_string(),
        Some(Value::Binary(b)) => String::from_utf8(b.clone()).map_err(|_| "array `dtype` is not valid UTF-8")?,
        Some(other) => return Err(format!("array `dtype` must be a string, found {}", kind(other))),
        None => return Err("array without `dtype`".into()),
    };
    let shape = match get(map, "shape") {
        Some(Value::Array(dims)) => dims
            .iter()
            .map(|d| d.as_u64().map(|n| n as usize).ok_or_else(|| format!("array `shape` entry {d} is not a size")))
            .collect::<Result<Vec<_>, _>>()?,
        Some(other) => return Err(format!("array `shape` must be a list, found {}", kind(other))),
        None => return Err("array without `shape`".into()),
    };
    Ok(Some(NdArray { dtype, shape, data }))
}

impl NdArray {
    /// Number of elements (`None` on overflow).
    pub fn len(&self) -> Option<usize> {
        self.shape.iter().try_fold(1usize, |acc, &d| acc.checked_mul(d))
    }

    pub fn is_empty(&self) -> bool {
        self.len() == Some(0)
    }

    /// The elements as `f64`, for `<f4` and `<f8` arrays whose byte count matches the shape.
    pub fn to_f64(&self) -> Result<Vec<f64>, String> {
        let size = match self.dtype.as_str() {
            "<f4" => 4,
            "<f8" => 8,
            other => return Err(format!("dtype {other:?} is not a float array (expected \"<f4\" or \"<f8\")")),
        };
        let n = self.len().ok_or("array shape overflows")?;
        if n.checked_mul(size) != Some(self.data.len()) {
            return Err(format!(
                "array of shape {:?} and dtype {} needs {} bytes of data, got {}",
                self.shape,
                self.dtype,
                n.saturating_mul(size),
                self.data.len()
            ));
        }
        Ok(if size == 4 {
            self.data.chunks_exact(4).map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))).collect()
        } else {
            self.data
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
                .collect()
        })
    }
}

/// The one msgpack document `bytes` holds; `what` names it in errors ("reply", "server
/// metadata"). A leading 0xc1, the byte msgpack never uses, is refused by name: the decoder
/// would read it as nil and the error would speak of a nil reply.
pub fn document(bytes: &[u8], what: &str) -> Result<Value, String> {
    if bytes.first() == Some(&0xc1) {
        return Err(format!("{what} is not a msgpack document: it starts with byte 0xc1, which msgpack never uses"));
    }
    let mut rest = bytes;
    let doc = rmpv::decode::read_value(&mut rest).map_err(|e| format!("{what} is not a msgpack document: {e}"))?;
    if !rest.is_empty() {
        return Err(format!("{what} is {} with {} unexpected bytes after it", kind(&doc), rest.len()));
    }
    Ok(doc)
}

/// A short name of a msgpack value's type, for error messages.
pub fn kind(v: &Value) -> &'static str {
    match v {
        Value::Nil => "nil",
        Value::Boolean(_) => "a boolean",
        Value::Integer(_) => "an integer",
        Value::F32(_) | Value::F64(_) => "a float",
        Value::String(_) => "a string",
        Value::Binary(_) => "bytes",
        Value::Array(_) => "a list",
        Value::Map(_) => "a map",
        Value::Ext(..) => "an extension value",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_document_is_one_msgpack_value_and_its_faults_are_named() {
        assert_eq!(document(&[0x81, 0xa1, b'a', 0x01], "reply"), Ok(Value::Map(vec![(Value::from("a"), Value::from(1))])));
        for (bytes, says) in [
            (&[0xc1, 0x00][..], "reply is not a msgpack document: it starts with byte 0xc1"),
            (&[][..], "reply is not a msgpack document"),
            (&[0x92, 0x01][..], "reply is not a msgpack document"),
            (&[0xc0, 0x01, 0x02][..], "reply is nil with 2 unexpected bytes after it"),
        ] {
            let err = document(bytes, "reply").unwrap_err();
            assert!(err.contains(says), "{bytes:?}: {err}");
        }
    }

    /// The byte-exact example of the research note (packed by openpi-client 0.1.2):
    /// `{"prompt": "hi", "observation/state": np.arange(6, dtype=float32).reshape(2, 3)}`.
    #[test]
    fn matches_python_bytes() {
        let data: Vec<u8> = (0..6).flat_map(|i| (i as f32).to_le_bytes()).collect();
        let doc = Value::Map(vec![
            (Value::from("prompt"), Value::from("hi")),
            (Value::from("observation/state"), encode("<f4", &[2, 3], data)),
        ]);
        let mut bytes = Vec::new();
        rmpv::encode::write_value(&mut bytes, &doc).unwrap();
        assert_eq!(bytes.len(), 97);
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        assert!(hex.starts_with("82a670726f6d7074a26869b1"), "{hex}");
        assert!(hex.contains("84c40b5f5f6e6461727261795f5fc3c40464617461c418"), "{hex}");
        assert!(hex.ends_with("c4056474797065a33c6634c4057368617065920203"), "{hex}");
        let back = rmpv::decode::read_value(&mut &bytes[..]).unwrap();
        let Value::Map(m) = &back else { panic!() };
        let arr = decode(get(m, "observation/state").unwrap()).unwrap().unwrap();
        assert_eq!(arr.shape, [2, 3]);
        assert_eq!(arr.to_f64().unwrap(), [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    }

    #[test]
    fn rejects_inconsistent_arrays() {
        let short = encode("<f8", &[2, 7], vec![0; 13 * 8]);
        let err = decode(&short).unwrap().unwrap().to_f64().unwrap_err();
        assert!(err.contains("needs 112 bytes") && err.contains("got 104"), "{err}");
        let ints = encode("<i8", &[1], vec![0; 8]);
        assert!(decode(&ints).unwrap().unwrap().to_f64().unwrap_err().contains("<i8"));
        let no_shape =
            Value::Map(vec![(bin_key("__ndarray__"), Value::Boolean(true)), (bin_key("data"), Value::Binary(vec![]))]);
        assert!(decode(&no_shape).unwrap_err().contains("dtype"));
        assert_eq!(decode(&Value::from(3)).unwrap(), None);
    }
}
