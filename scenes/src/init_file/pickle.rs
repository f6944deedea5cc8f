//! A pickle reader for exactly one thing: a numpy `float64` array as numpy and `torch.save`
//! write it (protocol 2 to 5).
//!
//! Nothing is executed. The opcode stream is interpreted with a stack and a memo, but only four
//! globals are understood, each by its known meaning: `numpy.core.multiarray._reconstruct`
//! (also `numpy._core`), `numpy.ndarray`, `numpy.dtype` and `_codecs.encode` (protocol 2 stores
//! the raw bytes as a latin-1 string re-encoded by that call). Any other global or opcode is
//! rejected with its byte offset.

use std::collections::HashMap;
use std::rc::Rc;

/// A decoded array in C (row-major) order.
#[derive(Clone, Debug, PartialEq)]
pub struct Array {
    pub shape: Vec<usize>,
    pub data: Vec<f64>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Global {
    Reconstruct,
    Ndarray,
    Dtype,
    Encode,
}

/// A float64 dtype; the byte order arrives with `BUILD`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Dtype {
    little_endian: Option<bool>,
}

/// Values are reference-counted so memo lookups stay cheap on hostile input.
#[derive(Clone, Debug)]
enum Value {
    None,
    Bool(bool),
    Int(i64),
    Str(Rc<str>),
    Bytes(Rc<[u8]>),
    Tuple(Rc<[Value]>),
    Mark,
    Global(Global),
    Dtype(Dtype),
    /// `_reconstruct` made an empty array; `BUILD` fills it.
    EmptyArray,
    Array(Rc<Array>),
}

impl Value {
    fn kind(&self) -> &'static str {
        match self {
            Value::None => "None",
            Value::Bool(_) => "a bool",
            Value::Int(_) => "an int",
            Value::Str(_) => "a string",
            Value::Bytes(_) => "bytes",
            Value::Tuple(_) => "a tuple",
            Value::Mark => "a mark",
            Value::Global(_) => "a global",
            Value::Dtype(_) => "a dtype",
            Value::EmptyArray | Value::Array(_) => "an array",
        }
    }
}

/// Reads the pickled array.
pub fn load_array(pickle: &[u8]) -> Result<Array, String> {
    let mut vm = Machine { input: pickle, at: 0, stack: Vec::new(), memo: HashMap::new() };
    vm.run().map_err(|message| format!("pickle byte {}: {message}", vm.at))
}

struct Machine<'a> {
    input: &'a [u8],
    at: usize,
    stack: Vec<Value>,
    memo: HashMap<u64, Value>,
}

impl Machine<'_> {
    fn take(&mut self, n: u64) -> Result<&[u8], String> {
        let remaining = (self.input.len() - self.at) as u64;
        if n > remaining {
            return Err(format!("needs {n} more bytes, only {remaining} left (truncated file?)"));
        }
        let start = self.at;
        self.at += n as usize;
        Ok(&self.input[start..self.at])
    }

    fn uint(&mut self, width: usize) -> Result<u64, String> {
        let bytes = self.take(width as u64)?;
        Ok(bytes.iter().rev().fold(0u64, |acc, &b| (acc << 8) | u64::from(b)))
    }

    fn line(&mut self) -> Result<String, String> {
        let rest = &self.input[self.at..];
        let end = rest.iter().position(|&b| b == b'\n').ok_or("unterminated GLOBAL name")?;
        let text = std::str::from_utf8(&rest[..end]).map_err(|_| "GLOBAL name is not UTF-8")?.to_string();
        self.at += end + 1;
        Ok(text)
    }

    fn text(&mut self, len: u64) -> Result<Value, String> {
        let bytes = self.take(len)?;
        let text = std::str::from_utf8(bytes).map_err(|_| "string is not UTF-8")?;
        Ok(Value::Str(Rc::from(text)))
    }

    fn bytes(&mut self, len: u64) -> Result<Value, String> {
        Ok(Value::Bytes(Rc::from(self.take(len)?)))
    }

    fn pop(&mut self) -> Result<Value, String> {
        self.stack.pop().ok_or_else(|| "stack underflow".to_string())
    }

    fn pop_str(&mut self, what: &str) -> Result<Rc<str>, String> {
        match self.pop()? {
            Value::Str(s) => Ok(s),
            other => Err(format!("expected {what} as a string, found {}", other.kind())),
        }
    }

    /// Pops everything above the topmost mark (and the mark).
    fn pop_to_mark(&mut self) -> Result<Vec<Value>, String> {
        let mark = self.stack.iter().rposition(|v| matches!(v, Value::Mark)).ok_or("TUPLE without MARK")?;
        let items = self.stack.split_off(mark + 1);
        self.stack.pop();
        Ok(items)
    }

    fn tuple(&mut self, n: usize) -> Result<(), String> {
        if self.stack.len() < n {
            return Err("stack underflow".into());
        }
        let items = self.stack.split_off(self.stack.len() - n);
        self.stack.push(Value::Tuple(Rc::from(items)));
        Ok(())
    }

    fn top(&self) -> Result<Value, String> {
        self.stack.last().cloned().ok_or_else(|| "stack underflow".to_string())
    }

    fn run(&mut self) -> Result<Array, String> {
        loop {
            let op = self.take(1)?[0];
            match op {
                0x80 => {
                    let protocol = self.uint(1)?;
                    if !(2..=5).contains(&protocol) {
                        return Err(format!("pickle protocol {protocol}; expected 2 to 5"));
                    }
                }
                0x95 => {
                    self.uint(8)?; // FRAME: a length hint only
                }
                b'c' => {
                    let module = self.line()?;
                    let name = self.line()?;
                    self.stack.push(Value::Global(global(&module, &name)?));
                }
                0x93 => {
                    let name = self.pop_str("STACK_GLOBAL name")?;
                    let module = self.pop_str("STACK_GLOBAL module")?;
                    self.stack.push(Value::Global(global(&module, &name)?));
                }
                b'X' => {
                    let len = self.uint(4)?;
                    let v = self.text(len)?;
                    self.stack.push(v);
                }
                0x8c => {
                    let len = self.uint(1)?;
                    let v = self.text(len)?;
                    self.stack.push(v);
                }
                0x8d => {
                    let len = self.uint(8)?;
                    let v = self.text(len)?;
                    self.stack.push(v);
                }
                b'C' => {
                    let len = self.uint(1)?;
                    let v = self.bytes(len)?;
                    self.stack.push(v);
                }
                b'B' => {
                    let len = self.uint(4)?;
                    let v = self.bytes(len)?;
                    self.stack.push(v);
                }
                0x8e => {
                    let len = self.uint(8)?;
                    let v = self.bytes(len)?;
                    self.stack.push(v);
                }
                b'q' => {
                    let key = self.uint(1)?;
                    let v = self.top()?;
                    self.memo.insert(key, v);
                }
                b'r' => {
                    let key = self.uint(4)?;
                    let v = self.top()?;
                    self.memo.insert(key, v);
                }
                0x94 => {
                    let key = self.memo.len() as u64;
                    let v = self.top()?;
                    self.memo.insert(key, v);
                }
                b'h' | b'j' => {
                    let key = self.uint(if op == b'h' { 1 } else { 4 })?;
                    let v = self.memo.get(&key).cloned().ok_or_else(|| format!("memo entry {key} is not set"))?;
                    self.stack.push(v);
                }
                b'K' => {
                    let v = self.uint(1)? as i64;
                    self.stack.push(Value::Int(v));
                }
                b'M' => {
                    let v = self.uint(2)? as i64;
                    self.stack.push(Value::Int(v));
                }
                b'J' => {
                    let v = self.uint(4)? as u32 as i32;
                    self.stack.push(Value::Int(i64::from(v)));
                }
                0x8a => {
                    let n = self.uint(1)? as usize;
                    if n > 8 {
                        return Err(format!("LONG1 of {n} bytes is too large"));
                    }
                    let raw = self.uint(n)?;
                    // Sign-extend the n-byte two's-complement value.
                    let shift = 64 - 8 * n as u32;
                    let v = if n == 0 { 0 } else { ((raw << shift) as i64) >> shift };
                    self.stack.push(Value::Int(v));
                }
                b'(' => self.stack.push(Value::Mark),
                b')' => self.stack.push(Value::Tuple(Rc::from(Vec::new()))),
                0x85 => self.tuple(1)?,
                0x86 => self.tuple(2)?,
                0x87 => self.tuple(3)?,
                b't' => {
                    let items = self.pop_to_mark()?;
                    self.stack.push(Value::Tuple(Rc::from(items)));
                }
                b'N' => self.stack.push(Value::None),
                0x88 => self.stack.push(Value::Bool(true)),
                0x89 => self.stack.push(Value::Bool(false)),
                b'R' => {
                    let args = self.pop()?;
                    let callable = self.pop()?;
                    let result = reduce(callable, args)?;
                    self.stack.push(result);
                }
                b'b' => {
                    let state = self.pop()?;
                    let object = self.pop()?;
                    let result = build(object, state)?;
                    self.stack.push(result);
                }
                b'.' => {
                    return match self.pop()? {
                        Value::Array(array) => Ok(Rc::unwrap_or_clone(array)),
                        other => Err(format!("the pickle holds {}, expected a numpy array", other.kind())),
                    };
                }
                other => {
                    let shown = if other.is_ascii_graphic() { format!(" '{}'", other as char) } else { String::new() };
                    return Err(format!(
                        "unsupported opcode 0x{other:02x}{shown}; only a numpy array as numpy/torch pickle it is understood"
                    ));
                }
            }
        }
    }
}

fn global(module: &str, name: &str) -> Result<Global, String> {
    match (module, name) {
        ("numpy.core.multiarray" | "numpy._core.multiarray", "_reconstruct") => Ok(Global::Reconstruct),
        ("numpy", "ndarray") => Ok(Global::Ndarray),
        ("numpy", "dtype") => Ok(Global::Dtype),
        ("_codecs", "encode") => Ok(Global::Encode),
        _ => Err(format!("global {module}.{name} is not allowed; expected only numpy array reconstruction")),
    }
}

fn items(value: &Value, what: &str) -> Result<Rc<[Value]>, String> {
    match value {
        Value::Tuple(items) => Ok(items.clone()),
        other => Err(format!("expected {what} as a tuple, found {}", other.kind())),
    }
}

fn reduce(callable: Value, args: Value) -> Result<Value, String> {
    let Value::Global(global) = callable else {
        return Err(format!("REDUCE on {}, expected a global", callable.kind()));
    };
    let args = items(&args, "REDUCE arguments")?;
    match (global, &args[..]) {
        (Global::Reconstruct, [Value::Global(Global::Ndarray), Value::Tuple(_), _]) => Ok(Value::EmptyArray),
        (Global::Dtype, [Value::Str(descr), ..]) if &**descr == "f8" => Ok(Value::Dtype(Dtype { little_endian: None })),
        (Global::Dtype, [Value::Str(descr), ..]) => Err(format!("expected a float64 ('f8') array, found dtype '{descr}'")),
        (Global::Encode, [Value::Str(text), Value::Str(codec)]) if matches!(&**codec, "latin1" | "latin-1") => {
            // Protocol 2 stores bytes as the latin-1 string with the same code points.
            let bytes: Result<Vec<u8>, _> = text.chars().map(u8::try_from).collect();
            let bytes = bytes.map_err(|_| "latin-1 text holds a character above U+00FF".to_string())?;
            Ok(Value::Bytes(Rc::from(bytes)))
        }
        (global, _) => Err(format!("unexpected arguments for {global:?}")),
    }
}

fn build(object: Value, state: Value) -> Result<Value, String> {
    let state = items(&state, "BUILD state")?;
    match object {
        Value::Dtype(_) => {
            // (version, byte order, subarray, names, fields, elsize, alignment, flags)
            let little_endian = match state.get(1) {
                Some(Value::Str(order)) if &**order == "<" => true,
                Some(Value::Str(order)) if &**order == ">" => false,
                _ => return Err("dtype state without '<' or '>' byte order".into()),
            };
            Ok(Value::Dtype(Dtype { little_endian: Some(little_endian) }))
        }
        Value::EmptyArray => {
            // (version, shape, dtype, is_fortran, raw data)
            let [_, Value::Tuple(shape), Value::Dtype(dtype), Value::Bool(fortran), Value::Bytes(raw)] = &state[..] else {
                return Err("array state is not (version, shape, dtype, fortran, bytes)".into());
            };
            if *fortran {
                return Err("Fortran-ordered arrays are not supported".into());
            }
            let little_endian = dtype.little_endian.ok_or("dtype without byte order")?;
            let shape = shape
                .iter()
                .map(|v| match v {
                    Value::Int(n) if *n >= 0 => Ok(*n as usize),
                    _ => Err("array shape holds a non-size".to_string()),
                })
                .collect::<Result<Vec<usize>, String>>()?;
            let count = shape.iter().try_fold(1usize, |acc, &n| acc.checked_mul(n)).ok_or("array shape overflows")?;
            if count.checked_mul(8) != Some(raw.len()) {
                return Err(format!("array of shape {shape:?} needs {count} × 8 bytes, the pickle holds {}", raw.len()));
            }
            let data = raw
                .chunks_exact(8)
                .map(|b| {
                    let b: [u8; 8] = b.try_into().expect("chunks_exact yields 8 bytes");
                    if little_endian { f64::from_le_bytes(b) } else { f64::from_be_bytes(b) }
                })
                .collect();
            Ok(Value::Array(Rc::new(Array { shape, data })))
        }
        other => Err(format!("BUILD on {}, expected a dtype or an array", other.kind())),
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Writes a (2, 3) float64 array the way numpy pickles it, in protocol 2 (bytes through
    /// `_codecs.encode`) or protocol 4 (raw bytes, `STACK_GLOBAL`, `MEMOIZE`, a frame).
    pub fn pickle_array(rows: usize, cols: usize, values: &[f64], protocol: u8) -> Vec<u8> {
        let mut p = vec![0x80, protocol];
        let global = |p: &mut Vec<u8>, module: &str, name: &str| {
            if protocol >= 4 {
                for s in [module, name] {
                    p.push(0x8c);
                    p.push(s.len() as u8);
                    p.extend_from_slice(s.as_bytes());
                }
                p.extend_from_slice(&[0x93, 0x94]);
            } else {
                p.extend_from_slice(format!("c{module}\n{name}\n").as_bytes());
            }
        };
        if protocol >= 4 {
            p.extend_from_slice(&[0x95, 0, 0, 0, 0, 0, 0, 0, 0]);
        }
        global(&mut p, "numpy.core.multiarray", "_reconstruct");
        global(&mut p, "numpy", "ndarray");
        p.extend_from_slice(&[b'K', 0, 0x85, b'C', 1, b'b', 0x87, b'R']);
        p.extend_from_slice(&[b'(', b'K', 1, b'K', rows as u8, b'K', cols as u8, 0x86]);
        global(&mut p, "numpy", "dtype");
        p.extend_from_slice(&[b'X', 2, 0, 0, 0, b'f', b'8', 0x89, 0x88, 0x87, b'R']);
        p.extend_from_slice(&[b'(', b'K', 3, b'X', 1, 0, 0, 0, b'<', b'N', b'N', b'N']);
        p.extend_from_slice(&[b'J', 0xff, 0xff, 0xff, 0xff, b'J', 0xff, 0xff, 0xff, 0xff, b'K', 0, b't', b'b', 0x89]);
        let raw: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        if protocol >= 3 {
            p.push(b'B');
            p.extend_from_slice(&(raw.len() as u32).to_le_bytes());
            p.extend_from_slice(&raw);
        } else {
            global(&mut p, "_codecs", "encode");
            let text: String = raw.iter().map(|&b| b as char).collect();
            p.push(b'X');
            p.extend_from_slice(&(text.len() as u32).to_le_bytes());
            p.extend_from_slice(text.as_bytes());
            p.extend_from_slice(&[b'X', 6, 0, 0, 0]);
            p.extend_from_slice(b"latin1");
            p.extend_from_slice(&[0x86, b'R']);
        }
        p.extend_from_slice(b"tb.");
        p
    }

    const VALUES: [f64; 6] = [0.0, -0.17673447526998573, 0.97, std::f64::consts::FRAC_1_SQRT_2, f64::MIN_POSITIVE, -2.5e300];

    #[test]
    fn reads_protocol_2_and_protocol_4_arrays_bit_for_bit() {
        for protocol in [2, 3, 4] {
            let array = load_array(&pickle_array(2, 3, &VALUES, protocol)).unwrap();
            assert_eq!(array.shape, [2, 3]);
            let bits: Vec<u64> = array.data.iter().map(|v| v.to_bits()).collect();
            assert_eq!(bits, VALUES.map(f64::to_bits), "protocol {protocol}");
        }
    }

    #[test]
    fn rejects_what_it_does_not_know() {
        let good = pickle_array(2, 3, &VALUES, 2);
        let replace = |from: &[u8], to: &[u8]| {
            let at = good.windows(from.len()).position(|w| w == from).unwrap();
            let mut bad = good[..at].to_vec();
            bad.extend_from_slice(to);
            bad.extend_from_slice(&good[at + from.len()..]);
            load_array(&bad).unwrap_err()
        };
        assert!(replace(b"numpy\ndtype", b"os\nsystem").contains("global os.system is not allowed"));
        assert!(replace(b"f8", b"i8").contains("expected a float64 ('f8') array, found dtype 'i8'"));
        assert!(replace(&[b'K', 1, b'K', 2], &[b'K', 1, b'K', 3]).contains("needs 9 × 8 bytes"));
        assert!(replace(&[0x89, b'c', b'_'], &[0x88, b'c', b'_']).contains("Fortran"));
        assert!(replace(&[0x80, 2], &[0x80, 1]).contains("protocol 1"));
        let err = replace(&[b'K', 0, 0x85], &[b'Q', 0, 0x85]);
        assert!(err.starts_with("pickle byte ") && err.contains("unsupported opcode 0x51 'Q'"), "{err}");
        assert!(load_array(&good[..good.len() - 1]).unwrap_err().contains("truncated"));
        assert!(load_array(&[0x80, 2, b'N', b'.']).unwrap_err().contains("holds None"));
    }

    #[test]
    fn never_panics_on_truncated_or_mutated_pickles() {
        let good = pickle_array(2, 3, &VALUES, 4);
        for cut in 0..good.len() {
            assert!(load_array(&good[..cut]).is_err());
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..20_000 {
            let mut bad = good.clone();
            for _ in 0..3 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let at = (state % bad.len() as u64) as usize;
                bad[at] = (state >> 32) as u8;
            }
            let _ = load_array(&bad);
        }
    }
}
