//! Python pickles as the pickle-speaking servers need them: a writer for the objects their
//! clients send (dicts, strings, ints, numpy arrays, PIL images, plain objects); replies are
//! read with the project's one pickle reader, `vifo_scenes::init_file::pickle`, re-exported
//! here.

pub use vifo_scenes::init_file::pickle::{Tensor, Value, read, read_all, tensor};

/// Builds a protocol-3 pickle (readable by every Python 3).
pub struct Writer {
    out: Vec<u8>,
}

impl Default for Writer {
    fn default() -> Self {
        Writer { out: vec![0x80, 3] }
    }
}

impl Writer {
    pub fn none(&mut self) {
        self.out.push(b'N');
    }

    pub fn bool(&mut self, b: bool) {
        self.out.push(if b { 0x88 } else { 0x89 });
    }

    pub fn int(&mut self, v: i64) {
        if let Ok(v) = i32::try_from(v) {
            self.out.push(b'J');
            self.out.extend(v.to_le_bytes());
        } else {
            // LONG1: little-endian two's complement, 8 bytes is always enough for an i64.
            self.out.extend([0x8a, 8]);
            self.out.extend(v.to_le_bytes());
        }
    }

    pub fn float(&mut self, v: f64) {
        self.out.push(b'G');
        self.out.extend(v.to_be_bytes());
    }

    pub fn str(&mut self, s: &str) {
        self.out.push(b'X');
        self.out.extend((s.len() as u32).to_le_bytes());
        self.out.extend(s.as_bytes());
    }

    pub fn bytes(&mut self, b: &[u8]) {
        self.out.push(b'B');
        self.out.extend((b.len() as u32).to_le_bytes());
        self.out.extend(b);
    }

    pub fn global(&mut self, module: &str, name: &str) {
        self.out.push(b'c');
        self.out.extend(module.as_bytes());
        self.out.push(b'\n');
        self.out.extend(name.as_bytes());
        self.out.push(b'\n');
    }

    pub fn mark(&mut self) {
        self.out.push(b'(');
    }

    /// Closes a tuple opened with [`Writer::mark`].
    pub fn tuple(&mut self) {
        self.out.push(b't');
    }

    pub fn empty_tuple(&mut self) {
        self.out.push(b')');
    }

    /// `callable(*args)`: callable and the args tuple are on the stack.
    pub fn reduce(&mut self) {
        self.out.push(b'R');
    }

    /// `cls.__new__(cls, *args)`.
    pub fn newobj(&mut self) {
        self.out.push(0x81);
    }

    /// `obj.__setstate__(state)` (or `obj.__dict__.update(state)`).
    pub fn build(&mut self) {
        self.out.push(b'b');
    }

    /// `[...]`: call, then push the items, then [`Writer::end_list`].
    pub fn begin_list(&mut self) {
        self.out.extend([b']', b'(']);
    }

    pub fn end_list(&mut self) {
        self.out.push(b'e');
    }

    /// `{...}`: call, then push keys and values, then [`Writer::end_dict`].
    pub fn begin_dict(&mut self) {
        self.out.extend([b'}', b'(']);
    }

    pub fn end_dict(&mut self) {
        self.out.push(b'u');
    }

    /// A tuple of ints (shapes, sizes).
    pub fn int_tuple(&mut self, xs: &[usize]) {
        self.mark();
        for &x in xs {
            self.int(x as i64);
        }
        self.tuple();
    }

    /// A numpy array as numpy pickles it: `_reconstruct(ndarray, (0,), b'b')`, then
    /// `__setstate__((1, shape, dtype, False, data))`. `descr` is numpy's `dtype.str`
    /// (`<f8`, `|u1`, …), `data` the C-order bytes.
    pub fn ndarray(&mut self, descr: &str, shape: &[usize], data: &[u8]) {
        self.global("numpy.core.multiarray", "_reconstruct");
        self.mark();
        self.global("numpy", "ndarray");
        self.int_tuple(&[0]);
        self.bytes(b"b");
        self.tuple();
        self.reduce();
        self.mark();
        self.int(1);
        self.int_tuple(shape);
        // np.dtype('f8', False, True) with state (3, '<', None, None, None, -1, -1, 0).
        let (order, code) = descr.split_at(1);
        self.global("numpy", "dtype");
        self.mark();
        self.str(code);
        self.bool(false);
        self.bool(true);
        self.tuple();
        self.reduce();
        self.mark();
        self.int(3);
        self.str(order);
        self.none();
        self.none();
        self.none();
        self.int(-1);
        self.int(-1);
        self.int(0);
        self.tuple();
        self.build();
        self.bool(false);
        self.bytes(data);
        self.tuple();
        self.build();
    }

    /// A `PIL.Image.Image` in mode RGB as Pillow pickles it: `Image.__new__(Image)`, then
    /// `__setstate__([info, mode, size, palette, data])`.
    pub fn pil_rgb(&mut self, width: u32, height: u32, data: &[u8]) {
        self.global("PIL.Image", "Image");
        self.empty_tuple();
        self.newobj();
        self.begin_list();
        self.begin_dict();
        self.end_dict();
        self.str("RGB");
        self.int_tuple(&[width as usize, height as usize]);
        self.none();
        self.bytes(data);
        self.end_list();
        self.build();
    }

    /// The finished pickle.
    pub fn finish(mut self) -> Vec<u8> {
        self.out.push(b'.');
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_values_read_back() {
        let mut w = Writer::default();
        w.begin_dict();
        w.str("n");
        w.int(5_000_000_000);
        w.str("neg");
        w.int(-3);
        w.str("x");
        w.float(0.25);
        w.str("s");
        w.str("héllo");
        w.end_dict();
        let v = read_all(&w.finish()).unwrap();
        assert_eq!(v.get("n"), Some(&Value::Int(5_000_000_000)));
        assert_eq!(v.get("neg"), Some(&Value::Int(-3)));
        assert_eq!(v.get("x"), Some(&Value::Float(0.25)));
        assert_eq!(v.get("s"), Some(&Value::Str("héllo".into())));
    }

    #[test]
    fn numpy_arrays_round_trip() {
        let mut w = Writer::default();
        let data: Vec<u8> = [1.5f64, -2.0, 3.25, 4.0].iter().flat_map(|x| x.to_le_bytes()).collect();
        w.ndarray("<f8", &[2, 2], &data);
        let t = tensor(&read_all(&w.finish()).unwrap()).unwrap();
        assert_eq!((t.shape, t.values, t.dtype.as_str()), (vec![2, 2], vec![1.5, -2.0, 3.25, 4.0], "<f8"));
    }
}
