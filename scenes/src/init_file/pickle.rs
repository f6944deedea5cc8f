//! The project's one Python pickle reader: LIBERO's init-state files (`torch.save` archives of
//! a numpy `float64` array) and the replies of pickle-speaking policy servers (torch tensors,
//! numpy arrays) both come through it.
//!
//! Nothing is executed: the opcode stream (protocols 0 to 5) is rebuilt as a graph of
//! [`Value`]s with calls (`REDUCE`) and objects (`NEWOBJ` + `BUILD`) kept symbolic, and
//! [`tensor`] then recognises the two array layouts by their globals (numpy's
//! `_reconstruct` with a `numpy.dtype`, torch's `_rebuild_tensor_v2`); anything else is an
//! error saying what the value is. Copies through the memo are budgeted, and the memo holds only
//! the entries put (any index, as `pickle.py`'s memo dict), so a hostile pickle cannot exhaust memory.
//!
//! Written by hand (no crate reads torch's nested legacy `torch.save` stream or numpy's
//! protocol-2 layout); the opcodes and layouts follow CPython's `pickletools` documentation,
//! numpy's `ndarray.__reduce__` and torch's `Tensor.__reduce_ex__` / `TypedStorage.__reduce__`.

use std::collections::BTreeMap;
use std::fmt;

/// A pickled value, symbolically.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    None,
    Bool(bool),
    Int(i64),
    /// An int beyond 64 bits: little-endian two's complement bytes.
    BigInt(Vec<u8>),
    Float(f64),
    Str(String),
    Bytes(Vec<u8>),
    Tuple(Vec<Value>),
    List(Vec<Value>),
    Dict(Vec<(Value, Value)>),
    /// A module-level name (`GLOBAL` / `STACK_GLOBAL`).
    Global(String, String),
    /// `callable(*args)` (`REDUCE`, `NEWOBJ`), with the state `BUILD` gave it, if any.
    Call {
        callable: Box<Value>,
        args: Box<Value>,
        state: Option<Box<Value>>,
    },
    /// A persistent id (`BINPERSID`), as torch's storages use.
    PersistentId(Box<Value>),
}

impl Value {
    /// A short name of the value's kind, for error messages.
    pub fn kind(&self) -> String {
        match self {
            Value::None => "None".into(),
            Value::Bool(_) => "a bool".into(),
            Value::Int(_) | Value::BigInt(_) => "an int".into(),
            Value::Float(_) => "a float".into(),
            Value::Str(_) => "a str".into(),
            Value::Bytes(_) => "bytes".into(),
            Value::Tuple(_) => "a tuple".into(),
            Value::List(_) => "a list".into(),
            Value::Dict(_) => "a dict".into(),
            Value::Global(m, n) => format!("{m}.{n}"),
            Value::Call { callable, .. } => format!("a {} object", callable.kind()),
            Value::PersistentId(_) => "a persistent id".into(),
        }
    }

    /// The entry under the string key `key` of a dict.
    pub fn get(&self, key: &str) -> Option<&Value> {
        match self {
            Value::Dict(items) => items.iter().find(|(k, _)| matches!(k, Value::Str(s) if s == key)).map(|(_, v)| v),
            _ => None,
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.kind())
    }
}


// ---------------------------------------------------------------------------------------------
// Reader

/// Reads one pickle from the start of `bytes`; returns the value and the bytes after it.
pub fn read(bytes: &[u8]) -> Result<(Value, &[u8]), String> {
    let mut r =
        Reader { data: bytes, pos: 0, stack: Vec::new(), marks: Vec::new(), memo: BTreeMap::new(), budget: COPY_BUDGET };
    let v = r.run()?;
    Ok((v, &bytes[r.pos..]))
}

/// Reads a pickle that must span all of `bytes`.
pub fn read_all(bytes: &[u8]) -> Result<Value, String> {
    let (v, rest) = read(bytes)?;
    if !rest.is_empty() {
        return Err(format!("{} unexpected bytes after the pickle", rest.len()));
    }
    Ok(v)
}

/// How much a pickle may copy through its memo (`GET`, `DUP`, `MEMOIZE`), in [`weight`] units
/// (nodes and bytes): action replies copy a few kB; a pickle that doubles a list on every step
/// is refused instead of exhausting memory.
const COPY_BUDGET: usize = 1 << 22;

struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    stack: Vec<Value>,
    marks: Vec<usize>,
    /// By index, like `pickle.py`'s memo dict: a `PUT` of index 4 billion costs one entry.
    memo: BTreeMap<usize, Value>,
    budget: usize,
}

/// Nodes plus bytes of a value, counted until `limit` is passed.
fn weight(v: &Value, limit: usize) -> usize {
    let mut total = 1;
    let mut todo = vec![v];
    while let Some(v) = todo.pop() {
        total += match v {
            Value::Str(s) => s.len(),
            Value::Bytes(b) | Value::BigInt(b) => b.len(),
            _ => 1,
        };
        if total > limit {
            break;
        }
        match v {
            Value::Tuple(xs) | Value::List(xs) => todo.extend(xs),
            Value::Dict(items) => todo.extend(items.iter().flat_map(|(k, v)| [k, v])),
            Value::Call { callable, args, state } => {
                todo.push(callable);
                todo.push(args);
                todo.extend(state.as_deref());
            }
            Value::PersistentId(id) => todo.push(id),
            _ => {}
        }
    }
    total
}

impl Reader<'_> {
    /// Charges a copy of `v` to the budget.
    fn charge(&mut self, v: &Value) -> Result<(), String> {
        let w = weight(v, self.budget);
        self.budget = self.budget.checked_sub(w).ok_or("pickle copies too much through its memo")?;
        Ok(())
    }

    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.data.len()).ok_or_else(|| {
            format!("pickle truncated: {n} bytes wanted at offset {}, {} left", self.pos, self.data.len() - self.pos)
        })?;
        let s = &self.data[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn u8(&mut self) -> Result<usize, String> {
        Ok(self.take(1)?[0] as usize)
    }

    fn u32(&mut self) -> Result<usize, String> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    }

    fn u64(&mut self) -> Result<usize, String> {
        let b = self.take(8)?;
        usize::try_from(u64::from_le_bytes(b.try_into().expect("8 bytes")))
            .map_err(|_| "pickle length overflows".into())
    }

    fn line(&mut self) -> Result<String, String> {
        let rest = &self.data[self.pos..];
        let n = rest.iter().position(|&b| b == b'\n').ok_or("pickle: unterminated text line")?;
        let s = String::from_utf8(rest[..n].to_vec()).map_err(|_| "pickle: text line is not UTF-8")?;
        self.pos += n + 1;
        Ok(s)
    }

    fn pop(&mut self) -> Result<Value, String> {
        self.stack.pop().ok_or_else(|| "pickle: stack underflow".to_string())
    }

    fn pop_mark(&mut self) -> Result<Vec<Value>, String> {
        let m = self.marks.pop().ok_or("pickle: no mark")?;
        if m > self.stack.len() {
            return Err("pickle: mark beyond the stack".into());
        }
        Ok(self.stack.split_off(m))
    }

    fn top(&mut self) -> Result<&mut Value, String> {
        self.stack.last_mut().ok_or_else(|| "pickle: stack underflow".to_string())
    }

    fn string(&mut self, n: usize) -> Result<Value, String> {
        let b = self.take(n)?.to_vec();
        String::from_utf8(b).map(Value::Str).map_err(|_| "pickle: string is not UTF-8".into())
    }

    fn memo_put(&mut self, i: usize) -> Result<(), String> {
        let v = self.stack.last().cloned().ok_or("pickle: memoize on an empty stack")?;
        self.charge(&v)?;
        self.memo.insert(i, v);
        Ok(())
    }

    fn memo_get(&mut self, i: usize) -> Result<(), String> {
        let v = self.memo.get(&i).cloned().ok_or_else(|| format!("pickle: memo {i} is empty"))?;
        self.charge(&v)?;
        self.stack.push(v);
        Ok(())
    }

    fn set_items(&mut self, items: Vec<Value>) -> Result<(), String> {
        if !items.len().is_multiple_of(2) {
            return Err("pickle: odd number of dict items".into());
        }
        let Value::Dict(d) = self.top()? else {
            return Err("pickle: SETITEMS on a non-dict".into());
        };
        let mut it = items.into_iter();
        while let (Some(k), Some(v)) = (it.next(), it.next()) {
            d.push((k, v));
        }
        Ok(())
    }

    fn run(&mut self) -> Result<Value, String> {
        loop {
            let op = self.take(1)?[0];
            match op {
                0x80 => {
                    let p = self.u8()?;
                    if p > 5 {
                        return Err(format!("pickle protocol {p} is not supported"));
                    }
                }
                0x95 => {
                    self.u64()?;
                }
                b'.' => return self.pop(),
                b'(' => self.marks.push(self.stack.len()),
                b'0' => {
                    self.pop()?;
                }
                b'1' => {
                    self.pop_mark()?;
                }
                b'2' => {
                    let v = self.top()?.clone();
                    self.charge(&v)?;
                    self.stack.push(v);
                }
                b'N' => self.stack.push(Value::None),
                0x88 => self.stack.push(Value::Bool(true)),
                0x89 => self.stack.push(Value::Bool(false)),
                b'J' => {
                    let b = self.take(4)?;
                    let v = Value::Int(i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as i64);
                    self.stack.push(v);
                }
                b'K' => {
                    let v = self.u8()?;
                    self.stack.push(Value::Int(v as i64));
                }
                b'M' => {
                    let b = self.take(2)?;
                    let v = Value::Int(u16::from_le_bytes([b[0], b[1]]) as i64);
                    self.stack.push(v);
                }
                0x8a | 0x8b => {
                    let n = if op == 0x8a { self.u8()? } else { self.u32()? };
                    let b = self.take(n)?;
                    if n > 8 {
                        let big = Value::BigInt(b.to_vec());
                        self.stack.push(big);
                        continue;
                    }
                    let mut buf = if b.last().is_some_and(|&x| x & 0x80 != 0) { [0xff; 8] } else { [0; 8] };
                    buf[..n].copy_from_slice(b);
                    self.stack.push(Value::Int(i64::from_le_bytes(buf)));
                }
                b'I' => {
                    let l = self.line()?;
                    let v = match l.as_str() {
                        "01" => Value::Bool(true),
                        "00" => Value::Bool(false),
                        s => Value::Int(s.parse().map_err(|_| format!("pickle: bad INT {s:?}"))?),
                    };
                    self.stack.push(v);
                }
                b'G' => {
                    let b = self.take(8)?;
                    let v = Value::Float(f64::from_be_bytes(b.try_into().expect("8 bytes")));
                    self.stack.push(v);
                }
                0x8c => {
                    let n = self.u8()?;
                    let v = self.string(n)?;
                    self.stack.push(v);
                }
                b'X' => {
                    let n = self.u32()?;
                    let v = self.string(n)?;
                    self.stack.push(v);
                }
                0x8d => {
                    let n = self.u64()?;
                    let v = self.string(n)?;
                    self.stack.push(v);
                }
                b'C' | b'B' | 0x8e | 0x96 | b'U' | b'T' => {
                    let n = match op {
                        b'C' | b'U' => self.u8()?,
                        b'B' | b'T' => self.u32()?,
                        _ => self.u64()?,
                    };
                    let b = self.take(n)?.to_vec();
                    self.stack.push(Value::Bytes(b));
                }
                0x98 => {}
                0x97 => return Err("pickle: out-of-band buffers are not supported".into()),
                b')' => self.stack.push(Value::Tuple(vec![])),
                b't' => {
                    let items = self.pop_mark()?;
                    self.stack.push(Value::Tuple(items));
                }
                0x85..=0x87 => {
                    let n = (op - 0x84) as usize;
                    if self.stack.len() < n {
                        return Err("pickle: stack underflow".into());
                    }
                    let items = self.stack.split_off(self.stack.len() - n);
                    self.stack.push(Value::Tuple(items));
                }
                b']' => self.stack.push(Value::List(vec![])),
                b'l' => {
                    let items = self.pop_mark()?;
                    self.stack.push(Value::List(items));
                }
                b'a' => {
                    let v = self.pop()?;
                    let Value::List(l) = self.top()? else {
                        return Err("pickle: APPEND to a non-list".into());
                    };
                    l.push(v);
                }
                b'e' => {
                    let items = self.pop_mark()?;
                    let Value::List(l) = self.top()? else {
                        return Err("pickle: APPENDS to a non-list".into());
                    };
                    l.extend(items);
                }
                b'}' => self.stack.push(Value::Dict(vec![])),
                b'd' => {
                    let items = self.pop_mark()?;
                    self.stack.push(Value::Dict(vec![]));
                    self.set_items(items)?;
                }
                b's' => {
                    let v = self.pop()?;
                    let k = self.pop()?;
                    self.set_items(vec![k, v])?;
                }
                b'u' => {
                    let items = self.pop_mark()?;
                    self.set_items(items)?;
                }
                0x8f => self.stack.push(Value::List(vec![])),
                0x90 => {
                    let items = self.pop_mark()?;
                    let Value::List(l) = self.top()? else {
                        return Err("pickle: ADDITEMS to a non-set".into());
                    };
                    l.extend(items);
                }
                0x91 => {
                    let items = self.pop_mark()?;
                    self.stack.push(Value::List(items));
                }
                b'c' => {
                    let module = self.line()?;
                    let name = self.line()?;
                    self.stack.push(Value::Global(module, name));
                }
                0x93 => {
                    let name = self.pop()?;
                    let module = self.pop()?;
                    match (module, name) {
                        (Value::Str(m), Value::Str(n)) => self.stack.push(Value::Global(m, n)),
                        _ => return Err("pickle: STACK_GLOBAL needs two strings".into()),
                    }
                }
                b'R' | 0x81 => {
                    let args = self.pop()?;
                    let callable = self.pop()?;
                    self.stack.push(Value::Call { callable: Box::new(callable), args: Box::new(args), state: None });
                }
                0x92 => {
                    let _kwargs = self.pop()?;
                    let args = self.pop()?;
                    let callable = self.pop()?;
                    self.stack.push(Value::Call { callable: Box::new(callable), args: Box::new(args), state: None });
                }
                b'b' => {
                    let s = self.pop()?;
                    match self.top()? {
                        Value::Call { state, .. } => *state = Some(Box::new(s)),
                        other => return Err(format!("pickle: BUILD on {}", other.kind())),
                    }
                }
                b'Q' => {
                    let id = self.pop()?;
                    self.stack.push(Value::PersistentId(Box::new(id)));
                }
                0x94 => {
                    // MEMOIZE: the next index is the memo's size, as in Python.
                    let i = self.memo.len();
                    self.memo_put(i)?;
                }
                b'q' => {
                    let i = self.u8()?;
                    self.memo_put(i)?;
                }
                b'r' => {
                    let i = self.u32()?;
                    self.memo_put(i)?;
                }
                b'p' => {
                    let i = self.line()?.parse().map_err(|_| "pickle: bad PUT index")?;
                    self.memo_put(i)?;
                }
                b'h' => {
                    let i = self.u8()?;
                    self.memo_get(i)?;
                }
                b'j' => {
                    let i = self.u32()?;
                    self.memo_get(i)?;
                }
                b'g' => {
                    let i = self.line()?.parse().map_err(|_| "pickle: bad GET index")?;
                    self.memo_get(i)?;
                }
                other => {
                    return Err(format!("pickle opcode 0x{other:02x} at offset {} is not supported", self.pos - 1));
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Arrays

/// A float array read from a pickle.
#[derive(Clone, Debug, PartialEq)]
pub struct Tensor {
    pub shape: Vec<usize>,
    /// Row-major values.
    pub values: Vec<f64>,
    /// Element type as numpy or torch names it (`<f4`, `torch.BFloat16Storage`, …).
    pub dtype: String,
}

fn global_of(v: &Value) -> Option<(&str, &str)> {
    match v {
        Value::Call { callable, .. } => match callable.as_ref() {
            Value::Global(m, n) => Some((m, n)),
            _ => None,
        },
        _ => None,
    }
}

fn ints(v: &Value, what: &str) -> Result<Vec<usize>, String> {
    match v {
        Value::Tuple(xs) | Value::List(xs) => xs
            .iter()
            .map(|x| match x {
                Value::Int(i) if *i >= 0 => Ok(*i as usize),
                other => Err(format!("{what} holds {}", other.kind())),
            })
            .collect(),
        other => Err(format!("{what} is {}, expected a tuple of ints", other.kind())),
    }
}

/// Decodes one element type into f64s; `None` for types that are not floats or bytes that are
/// not a whole number of elements.
fn floats(kind: &str, bytes: &[u8]) -> Option<Vec<f64>> {
    let size = match kind {
        "f8" => 8,
        "f4" => 4,
        _ => 2,
    };
    if !bytes.len().is_multiple_of(size) {
        return None;
    }
    Some(match kind {
        "f8" => bytes.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes"))).collect(),
        "f4" => bytes.chunks_exact(4).map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))).collect(),
        "f2" => bytes.chunks_exact(2).map(|b| f16_to_f64(u16::from_le_bytes([b[0], b[1]]))).collect(),
        "bf16" => bytes
            .chunks_exact(2)
            .map(|b| f64::from(f32::from_bits(u32::from(u16::from_le_bytes([b[0], b[1]])) << 16)))
            .collect(),
        _ => return None,
    })
}

fn f16_to_f64(h: u16) -> f64 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = i32::from((h >> 10) & 0x1f);
    let frac = f64::from(h & 0x3ff);
    sign * match exp {
        0 => frac * 2f64.powi(-24),
        31 if frac == 0.0 => f64::INFINITY,
        31 => f64::NAN,
        e => (1.0 + frac / 1024.0) * 2f64.powi(e - 15),
    }
}

/// A torch tensor or numpy array as a [`Tensor`]; `Err` says what the value is instead.
pub fn tensor(v: &Value) -> Result<Tensor, String> {
    match global_of(v) {
        Some(("torch._utils", "_rebuild_tensor_v2")) => torch_tensor(v),
        Some((m, "_reconstruct")) if m.ends_with("multiarray") => numpy_array(v),
        _ => Err(format!("{}, expected a torch tensor or a numpy array", v.kind())),
    }
}

fn numpy_array(v: &Value) -> Result<Tensor, String> {
    let Value::Call { state: Some(state), .. } = v else {
        return Err("numpy array without state".into());
    };
    let Value::Tuple(s) = state.as_ref() else {
        return Err("numpy array state is not a tuple".into());
    };
    let [_, shape, dtype, fortran, data] = s.as_slice() else {
        return Err(format!("numpy array state has {} entries, expected 5", s.len()));
    };
    let shape = ints(shape, "numpy shape")?;
    if *fortran != Value::Bool(false) {
        return Err("numpy array in Fortran order".into());
    }
    if global_of(dtype) != Some(("numpy", "dtype")) {
        return Err(format!("numpy array dtype is {}, expected a numpy.dtype", dtype.kind()));
    }
    let Value::Call { args, state: dstate, .. } = dtype else { unreachable!("checked above") };
    let code = match args.as_ref() {
        Value::Tuple(a) => match a.first() {
            Some(Value::Str(c)) => c.clone(),
            _ => return Err("numpy dtype without a type code".into()),
        },
        _ => return Err("numpy dtype args are not a tuple".into()),
    };
    let order = match dstate.as_deref() {
        Some(Value::Tuple(d)) => match d.get(1) {
            Some(Value::Str(o)) => o.clone(),
            _ => "|".into(),
        },
        _ => "|".into(),
    };
    let dtype = format!("{order}{code}");
    let mut bytes = numpy_bytes(data)?;
    if !matches!(code.as_str(), "f2" | "f4" | "f8") {
        return Err(format!("numpy dtype {dtype:?} is not a float type"));
    }
    if order == ">" {
        let size = code[1..].parse::<usize>().expect("f2, f4 or f8");
        bytes.chunks_mut(size).for_each(<[u8]>::reverse);
    }
    let values =
        floats(&code, &bytes).ok_or_else(|| format!("numpy data of {} bytes is not {dtype} elements", bytes.len()))?;
    let n = shape.iter().try_fold(1usize, |a, &d| a.checked_mul(d)).ok_or("numpy shape overflows")?;
    if values.len() != n {
        return Err(format!("numpy array of shape {shape:?} has {} values", values.len()));
    }
    Ok(Tensor { shape, values, dtype })
}

/// The raw bytes of a numpy array: protocol 3+ stores them as bytes, protocol 2 (torch.save's
/// default) as the latin-1 string of the same code points passed through `_codecs.encode`.
fn numpy_bytes(data: &Value) -> Result<Vec<u8>, String> {
    match data {
        Value::Bytes(b) => Ok(b.clone()),
        Value::Call { args, .. } if global_of(data) == Some(("_codecs", "encode")) => match args.as_ref() {
            Value::Tuple(a) => match a.as_slice() {
                [Value::Str(text), Value::Str(codec)] if matches!(codec.as_str(), "latin1" | "latin-1") => text
                    .chars()
                    .map(|c| u8::try_from(c).map_err(|_| "numpy data: latin-1 text holds a character above U+00FF".to_string()))
                    .collect(),
                _ => Err("numpy data: _codecs.encode without (text, 'latin1')".into()),
            },
            _ => Err("numpy data: _codecs.encode args are not a tuple".into()),
        },
        other => Err(format!("numpy data is {}", other.kind())),
    }
}

/// The float64 array a LIBERO init-state file holds (`torch.save` of a numpy array); any other
/// content is an error naming what was found.
pub fn load_array(pickle: &[u8]) -> Result<Tensor, String> {
    let array = tensor(&read_all(pickle)?)?;
    if !array.dtype.ends_with("f8") {
        return Err(format!("expected a float64 ('f8') array, found dtype '{}'", array.dtype));
    }
    Ok(array)
}

/// Tensors above this many elements are refused (an action chunk has a few hundred).
const MAX_ELEMENTS: usize = 1 << 24;

fn torch_tensor(v: &Value) -> Result<Tensor, String> {
    let Value::Call { args, .. } = v else { unreachable!("checked by the caller") };
    let Value::Tuple(a) = args.as_ref() else {
        return Err("tensor args are not a tuple".into());
    };
    if a.len() < 4 {
        return Err(format!("tensor args have {} entries, expected at least 4", a.len()));
    }
    let offset = match &a[1] {
        Value::Int(o) if *o >= 0 => *o as usize,
        other => return Err(format!("tensor storage offset is {}", other.kind())),
    };
    let shape = ints(&a[2], "tensor size")?;
    let stride = ints(&a[3], "tensor stride")?;
    if stride.len() != shape.len() {
        return Err("tensor size and stride differ in length".into());
    }
    let (storage_type, data) = match global_of(&a[0]) {
        Some(("torch.storage", "_load_from_bytes")) => {
            let Value::Call { args, .. } = &a[0] else { unreachable!() };
            match args.as_ref() {
                Value::Tuple(x) => match x.as_slice() {
                    [Value::Bytes(b)] => legacy_storage(b)?,
                    _ => return Err("_load_from_bytes without bytes".into()),
                },
                _ => return Err("_load_from_bytes args are not a tuple".into()),
            }
        }
        _ => {
            return Err(format!("tensor storage is {}, expected torch.storage._load_from_bytes", a[0].kind()));
        }
    };
    let code = match storage_type.as_str() {
        "FloatStorage" => "f4",
        "DoubleStorage" => "f8",
        "HalfStorage" => "f2",
        "BFloat16Storage" => "bf16",
        other => return Err(format!("tensor of torch.{other} is not a float tensor")),
    };
    let all = floats(code, &data).ok_or("torch storage is not a whole number of elements")?;
    let n = shape.iter().try_fold(1usize, |a, &d| a.checked_mul(d)).filter(|&n| n <= MAX_ELEMENTS);
    let n = n.ok_or_else(|| format!("tensor of size {shape:?} is larger than {MAX_ELEMENTS} elements"))?;
    let mut values = Vec::with_capacity(n);
    let mut index = vec![0usize; shape.len()];
    for _ in 0..n {
        let at = index
            .iter()
            .zip(&stride)
            .try_fold(offset, |acc, (i, s)| i.checked_mul(*s).and_then(|x| acc.checked_add(x)))
            .unwrap_or(usize::MAX);
        values.push(*all.get(at).ok_or_else(|| format!("tensor element {at} is beyond its storage of {}", all.len()))?);
        for d in (0..shape.len()).rev() {
            index[d] += 1;
            if index[d] < shape[d] {
                break;
            }
            index[d] = 0;
        }
    }
    Ok(Tensor { shape, values, dtype: format!("torch.{storage_type}") })
}

/// torch's legacy `torch.save` stream of one storage (what `TypedStorage.__reduce__` embeds):
/// pickles of the magic number, the protocol version and the system info, then the storage
/// as a persistent id `('storage', torch.<Type>Storage, key, location, numel, view)`, then the
/// sorted list of keys, then per key an int64 element count and the raw little-endian data.
/// `torch.serialization.MAGIC_NUMBER` (0x1950a86a20f9469cfc6c) as pickle's LONG1 bytes.
const TORCH_MAGIC: [u8; 10] = [0x6c, 0xfc, 0x9c, 0x46, 0xf9, 0x20, 0x6a, 0xa8, 0x50, 0x19];

fn legacy_storage(b: &[u8]) -> Result<(String, Vec<u8>), String> {
    let (magic, rest) = read(b)?;
    if magic != Value::BigInt(TORCH_MAGIC.to_vec()) {
        return Err("torch storage stream without its magic number".into());
    }
    let (_version, rest) = read(rest)?;
    let (_sys_info, rest) = read(rest)?;
    let (obj, rest) = read(rest)?;
    let (keys, mut rest) = read(rest)?;
    let Value::PersistentId(id) = obj else {
        return Err(format!("torch storage stream holds {}", obj.kind()));
    };
    let Value::Tuple(id) = *id else {
        return Err("torch storage id is not a tuple".into());
    };
    let (storage_type, key) = match id.as_slice() {
        [Value::Str(tag), Value::Global(m, t), Value::Str(key), ..] if tag == "storage" && m == "torch" => {
            (t.clone(), key.clone())
        }
        _ => return Err("torch storage id is not ('storage', torch.<Type>Storage, key, …)".into()),
    };
    let element = match storage_type.as_str() {
        "DoubleStorage" | "LongStorage" => 8,
        "FloatStorage" | "IntStorage" => 4,
        "HalfStorage" | "BFloat16Storage" | "ShortStorage" => 2,
        _ => 1,
    };
    let Value::List(keys) = keys else {
        return Err("torch storage keys are not a list".into());
    };
    for k in keys {
        if rest.len() < 8 {
            return Err("torch storage data truncated".into());
        }
        let numel = u64::from_le_bytes(rest[..8].try_into().expect("8 bytes")) as usize;
        let len = numel.checked_mul(element).filter(|&l| l <= rest.len() - 8).ok_or("torch storage data truncated")?;
        let data = &rest[8..8 + len];
        if k == Value::Str(key.clone()) {
            return Ok((storage_type, data.to_vec()));
        }
        rest = &rest[8 + len..];
    }
    Err(format!("torch storage stream has no data for key {key:?}"))
}

#[cfg(test)]
pub(crate) mod tests {
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
            let bits: Vec<u64> = array.values.iter().map(|v| v.to_bits()).collect();
            assert_eq!(bits, VALUES.map(f64::to_bits), "protocol {protocol}");
        }
    }

    /// `bytes` with the first occurrence of `from` replaced by `to`.
    fn splice(bytes: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
        let at = bytes.windows(from.len()).position(|w| w == from).unwrap();
        [&bytes[..at], to, &bytes[at + from.len()..]].concat()
    }

    #[test]
    fn reads_big_endian_arrays() {
        let le: Vec<u8> = VALUES.iter().flat_map(|v| v.to_le_bytes()).collect();
        let be: Vec<u8> = VALUES.iter().flat_map(|v| v.to_be_bytes()).collect();
        let good = pickle_array(2, 3, &VALUES, 4);
        let big = splice(&splice(&good, &le, &be), &[b'X', 1, 0, 0, 0, b'<'], &[b'X', 1, 0, 0, 0, b'>']);
        let array = load_array(&big).unwrap();
        assert_eq!(array.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), VALUES.map(f64::to_bits));
    }

    #[test]
    fn rejects_what_it_does_not_know() {
        let good = pickle_array(2, 3, &VALUES, 2);
        let replace = |from: &[u8], to: &[u8]| load_array(&splice(&good, from, to)).unwrap_err();
        assert!(replace(b"numpy\ndtype", b"os\nsystem").contains("dtype is a os.system object, expected a numpy.dtype"));
        assert!(replace(b"f8", b"i8").contains("numpy dtype \"<i8\" is not a float type"));
        assert!(replace(&[b'K', 1, b'K', 2], &[b'K', 1, b'K', 3]).contains("shape [3, 3] has 6 values"));
        // float32 data that makes a whole array is read as a tensor, refused as init states.
        let f4 = load_array(&splice(&splice(&good, b"f8", b"f4"), &[b'K', 1, b'K', 2], &[b'K', 1, b'K', 4]));
        assert!(f4.unwrap_err().contains("expected a float64 ('f8') array, found dtype '<f4'"));
        assert!(replace(&[0x89, b'c', b'_'], &[0x88, b'c', b'_']).contains("Fortran"));
        assert!(replace(b"latin1", b"utf-8!").contains("_codecs.encode without (text, 'latin1')"));
        let err = replace(&[b'K', 0, 0x85], &[0xff, 0, 0x85]);
        assert!(err.contains("opcode 0xff at offset") && err.contains("not supported"), "{err}");
        assert!(load_array(&good[..good.len() - 1]).unwrap_err().contains("truncated"));
        assert!(load_array(&[0x80, 2, b'N', b'.']).unwrap_err().contains("None, expected a torch tensor or a numpy array"));
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

    #[test]
    fn bad_pickles_are_errors() {
        assert!(read_all(&[0x80, 3, b'J', 1]).unwrap_err().contains("truncated"));
        assert!(read_all(&[0x80, 3, 0xff]).unwrap_err().contains("0xff"));
        assert!(read_all(&[0x80, 3, b't']).unwrap_err().contains("mark"));
        assert!(read_all(&[0x80, 3, b'N', b'.', 0]).unwrap_err().contains("unexpected bytes"));
        assert!(tensor(&Value::Int(3)).unwrap_err().contains("an int"));
        // A list doubled 40 times through the memo would need 2^40 copies.
        let mut bomb = vec![0x80, 3, b']', 0x94];
        for i in 0..40u8 {
            bomb.extend([b'h', i, b'h', i, 0x86, 0x94]);
        }
        bomb.push(b'.');
        assert!(read_all(&bomb).unwrap_err().contains("copies too much"));
        // A pickle that puts at index 2^32 - 2 (a memo sized to its largest index takes
        // gigabytes: CPython's C unpickler raises MemoryError) is read as Python's own
        // `pickle._loads` reads it, and MEMOIZE then takes the memo's size, 1, as its index.
        let far = [0x80, 3, b'J', 7, 0, 0, 0, b'r', 0xfe, 0xff, 0xff, 0xff, 0x94, b'0', b'j', 0xfe, 0xff, 0xff, 0xff, b'h', 1, 0x86, b'.'];
        assert_eq!(read_all(&far).unwrap(), Value::Tuple(vec![Value::Int(7), Value::Int(7)]));
        assert_eq!(f16_to_f64(0x3c00), 1.0);
        assert_eq!(f16_to_f64(0xc000), -2.0);
    }
}
