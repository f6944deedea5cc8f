//! `vifo xval <dir>`: cross-validation against MuJoCo reference recordings.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use vifo::xval::projection::{self, ModelFacts, ProjectionSummary};
use vifo::look::{LookArgs, label};
use vifo::xval::{self, Recording, images};

#[derive(Args)]
pub struct XvalArgs {
    /// Directory laid out like LIBERO-VIFO's reference set (`*_init0.json` recordings).
    pub dir: PathBuf,
    /// Print one JSON object instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Render every record that has MuJoCo's images of both cameras (records 0 and 50 in the
    /// reference set; more in `xval/record_complete.py --actions` recordings) and write
    /// `MuJoCo | ours | difference` PNGs into this folder (prints PSNR and SSIM per image, and
    /// min/median/max per camera).
    #[arg(long, value_name = "OUT")]
    pub images: Option<PathBuf>,
    #[command(flatten)]
    pub look: LookArgs,
    /// Project every recorded object at records 0 and 50 with both cameras and compare with
    /// MuJoCo's projection from `model_facts.json`.
    #[arg(long)]
    pub projection: bool,
}

pub fn run(args: &XvalArgs) -> Result<()> {
    if let Some(out) = &args.images {
        return run_images(args, out);
    }
    if args.projection {
        return run_projection(args);
    }
    let mut reports = Vec::new();
    for path in xval::recordings_in(&args.dir)? {
        let rec = Recording::load(&path)?;
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        reports.push(xval::replay(&name, &rec).with_context(|| path.display().to_string())?);
    }
    let summary = xval::summarize(&reports);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "tasks": reports, "summary": summary }))?);
        return Ok(());
    }
    let w = reports.iter().map(|r| r.file.len()).max().unwrap_or(0).max(34);
    println!("Cross-validation against MuJoCo (full scene; end-effector from joint states)");
    println!("{:<w$} {:<9} {:>11} {:>11} {:>10} {:>11} {:>11} {:>11}", "file", "phase", "eef max mm", "eef rms mm", "rot max °", "joint max r", "finger mm", "1 step r");
    for r in &reports {
        for p in r.phases.iter().map(|p| (p.phase.as_str(), &p.stats)).chain([("all", &r.all)]) {
            let s = p.1;
            if s.records == 0 {
                println!("{:<w$} {:<9} {:>11}", r.file, p.0, "no records");
                continue;
            }
            println!(
                "{:<w$} {:<9} {:>11.3} {:>11.3} {:>10.3} {:>11.5} {:>11.3} {:>11.6}",
                r.file, p.0, s.eef_pos_max_m * 1e3, s.eef_pos_rms_m * 1e3, s.eef_rot_max_deg, s.joint_max_rad, s.finger_max_m * 1e3, s.step_joint_max_rad
            );
        }
    }
    println!();
    println!("{:<w$} {:<28} {:<7} {:>9} {:>9}", "file", "object", "at", "pos mm", "rot °");
    for r in &reports {
        for o in &r.objects {
            println!("{:<w$} {:<28} {:<7} {:>9.2} {:>9.2}", r.file, o.object, o.at, o.pos_m * 1e3, o.rot_deg);
        }
    }
    println!(
        "objects: settled position error median {:.2} mm, max {:.2} mm; at the end max {:.2} mm, {:.2}°",
        summary.obj_settle_pos_median_m * 1e3, summary.obj_settle_pos_max_m * 1e3, summary.obj_end_pos_max_m * 1e3, summary.obj_end_rot_max_deg
    );
    let s = &summary.stats;
    println!(
        "summary over {} tasks: eef_pos_max {:.3} mm, eef_pos_rms {:.3} mm, eef_rot_max {:.3}°, joint_max {:.5} rad, finger_max {:.3} mm, one step from MuJoCo's state: joint_max {:.6} rad",
        summary.tasks, s.eef_pos_max_m * 1e3, s.eef_pos_rms_m * 1e3, s.eef_rot_max_deg, s.joint_max_rad, s.finger_max_m * 1e3, s.step_joint_max_rad
    );
    println!("(\"1 step r\": the largest joint difference one control step after MuJoCo's recorded arm state; it does not accumulate)");
    Ok(())
}

fn run_images(args: &XvalArgs, out: &Path) -> Result<()> {
    let look = args.look.look()?;
    let mut reports = Vec::new();
    for path in xval::recordings_in(&args.dir)? {
        let compared = images::compare(&path, &Recording::load(&path)?, out, look.as_deref());
        reports.extend(compared.with_context(|| path.display().to_string())?);
    }
    let summary = images::summarize(&reports);
    let look = label(look.as_deref());
    if args.json {
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "look": look, "images": reports, "cameras": summary }))?);
        return Ok(());
    }
    println!("Our cameras against MuJoCo's images ({0}×{0}; MuJoCo | ours | difference ×4 in {1}); look {look}", images::IMAGE_SIZE, out.display());
    println!("{:<34} {:<20} {:>4} {:>9} {:>7}", "file", "camera", "t", "PSNR dB", "SSIM");
    for r in &reports {
        println!("{:<34} {:<20} {:>4} {:>9.2} {:>7.3}", r.file, r.camera, r.t, r.psnr_db, r.ssim);
    }
    println!();
    println!("{:<20} {:>6} {:>24} {:>24}", "camera", "images", "PSNR dB min/median/max", "SSIM min/median/max");
    for c in &summary {
        println!(
            "{:<20} {:>6} {:>8.2}/{:>7.2}/{:>7.2} {:>8.3}/{:>7.3}/{:>7.3}",
            c.camera, c.images, c.psnr_db.min, c.psnr_db.median, c.psnr_db.max, c.ssim.min, c.ssim.median, c.ssim.max
        );
    }
    Ok(())
}

fn run_projection(args: &XvalArgs) -> Result<()> {
    let facts = ModelFacts::load(&args.dir.join("model_facts.json"))?;
    let mut summary = ProjectionSummary::default();
    let mut files = Vec::new();
    for path in xval::recordings_in(&args.dir)? {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let projected = projection::project(&name, &Recording::load(&path)?, &facts, &mut summary);
        files.push(projected.with_context(|| path.display().to_string())?);
    }
    // No point inside MuJoCo's image would print a maximum of 0 px, which reads as a perfect match.
    anyhow::ensure!(summary.points > 0, "no recorded object falls inside MuJoCo's images of {}: nothing was compared", args.dir.display());
    if args.json {
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "files": files, "summary": summary }))?);
        return Ok(());
    }
    println!("{:<34} {:>4} {:<20} {:<32} {:>8} {:>8}", "file", "t", "camera", "object", "u", "v");
    for f in &files {
        for s in &f.steps {
            for (camera, pixels) in &s.cameras {
                for (object, px) in pixels {
                    let (u, v) = px.map_or((f64::NAN, f64::NAN), |[u, v]| (u, v));
                    println!("{:<34} {:>4} {:<20} {:<32} {:>8.2} {:>8.2}", f.file, s.t, camera, object, u, v);
                }
            }
        }
    }
    println!(
        "against MuJoCo over {} points in view: max {:.2e} px (agentview {:.2e} px, robot0_eye_in_hand {:.2e} px)",
        summary.points, summary.projection_max_px, summary.agentview_max_px, summary.eye_in_hand_max_px
    );
    Ok(())
}
