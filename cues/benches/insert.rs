//! Milliseconds per cue insertion into a 256² frame, per variant and family.
//!
//! Budget: ≤ 0.5 ms per insertion (≤ 3 ms for ghosts), after the first use of a spec has
//! filled the cache (the first-use time is printed too). Each timed insertion includes
//! copying the clean frame back (a 196 KB memcpy, well under 0.01 ms).
//!
//! `cargo bench -p vifo-cues --bench insert`

use std::time::Instant;

use vifo_cues::{
    Anchor, Anchors, CueSpec, Family, FrameInputs, Inserter, RgbImage, RgbaImage, VARIANTS, instances, parse,
};

const SIZE: u32 = 256;

fn disc(cx: f32, cy: f32, r: f32) -> RgbaImage {
    let mut img = RgbaImage::new(SIZE, SIZE).unwrap();
    for y in 0..SIZE {
        for x in 0..SIZE {
            if (x as f32 - cx).powi(2) + (y as f32 - cy).powi(2) <= r * r {
                let i = ((y * SIZE + x) * 4) as usize;
                img.data[i..i + 4].copy_from_slice(&[40, 40, 40, 255]);
            }
        }
    }
    img
}

fn main() {
    let parsed = parse("pick up the black bowl next to the plate and place it on the plate").unwrap();
    let base = RgbImage::filled(SIZE, SIZE, [120, 110, 100]).unwrap();
    let ghosts: Vec<RgbaImage> = (1..=5).map(|i| disc(70.0 + 23.0 * i as f32, 160.0 - 10.0 * i as f32, 14.0)).collect();
    let pictures = vec![disc(60.0, 160.0, 20.0), disc(180.0, 110.0, 20.0)];
    let iterations = 300;
    let mut worst: Vec<(Family, f64)> = Family::ALL.iter().map(|&f| (f, 0.0)).collect();
    println!("{:<4} {:<26} {:>10} {:>10}", "fam", "variant", "first ms", "ms/insert");
    for v in VARIANTS {
        let step = instances::step_for(&parsed, v.needs).unwrap_or(0);
        let spec = CueSpec::new("bench/0", &parsed, step, v).unwrap();
        let mut inserter = Inserter::new();
        let mut frame = base.clone();
        let anchors = |i: usize| Anchors {
            source: Some(Anchor::at(70.0 + (i % 7) as f64, 160.0).with_radius(16.0)),
            target: Some(Anchor::at(185.0, 110.0 + (i % 5) as f64).with_radius(22.0)),
        };
        let inputs0 = FrameInputs { anchors: anchors(0), ghost_layers: &ghosts, pictures: &pictures };
        let t0 = Instant::now();
        inserter.insert(&mut frame, &spec, &inputs0).unwrap();
        let first = t0.elapsed().as_secs_f64() * 1e3;
        let t = Instant::now();
        for i in 0..iterations {
            frame.data.copy_from_slice(&base.data);
            let inputs = FrameInputs { anchors: anchors(i), ghost_layers: &ghosts, pictures: &pictures };
            inserter.insert(&mut frame, &spec, &inputs).unwrap();
        }
        let per = t.elapsed().as_secs_f64() * 1e3 / iterations as f64;
        let budget = if v.family == Family::F3 { 3.0 } else { 0.5 };
        let flag = if per > budget { "  OVER BUDGET" } else { "" };
        println!("{:<4} {:<26} {:>10.3} {:>10.3}{flag}", v.family.to_string(), v.name, first, per);
        let w = worst.iter_mut().find(|(f, _)| *f == v.family).unwrap();
        w.1 = w.1.max(per);
    }
    println!();
    for (family, ms) in worst {
        println!("{family} {:<24} slowest variant {ms:.3} ms/insert", family.name());
    }
}
