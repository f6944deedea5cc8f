//! `vifo assets`: where LIBERO's asset files were found, which categories are drawn from them
//! and which keep the built-in look, and the content hash of the set.

use anyhow::Result;
use clap::Args;
use vifo::look::LookArgs;
use vifo_scenes::look::{FoundBy, Origin, Status};

#[derive(Args)]
pub struct AssetsArgs {
    #[command(flatten)]
    pub look: LookArgs,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &AssetsArgs) -> Result<()> {
    let look = args.look.load()?;
    let roots = look.roots();
    if args.json {
        let value = serde_json::json!({
            "look": look.label(),
            "hash": look.hash(),
            "roots": roots.libero,
            "robot": roots.robot,
            "notes": roots.notes,
            "categories": look.report(),
            "cache": look.cache(),
        });
        println!("{}", serde_json::to_string_pretty(&value)?);
        return Ok(());
    }
    let origin = |o: &Origin| match o {
        Origin::Flag => "--assets".to_string(),
        Origin::Env => vifo_scenes::look::ENV_VAR.to_string(),
        Origin::Python(p) => format!("python package {p}"),
    };
    println!("LIBERO asset folders, in lookup order:");
    if roots.libero.is_empty() {
        println!("  (none)");
    }
    for r in &roots.libero {
        println!("  {}  ({})", r.path.display(), origin(&r.origin));
    }
    match &roots.robot {
        Some(r) => println!("robot meshes: {}  ({})", r.path.display(), origin(&r.origin)),
        None => println!("robot meshes: not found (the robot keeps the built-in look)"),
    }
    println!("arena: floors, walls and the box table's top and sides from their textures, each scene's decor (with the living-room and study tables) from its meshes (below); the box table's legs keep their texture's mean colour (on a cylinder MuJoCo picks the cube face per pixel)");
    for n in &roots.notes {
        println!("note: {n}");
    }
    println!();
    println!("{:<30} {:<8} {:<9} files", "category", "kind", "look");
    for r in look.report() {
        let kind = format!("{:?}", r.kind).to_lowercase();
        let status = if r.status == Status::Assets { "assets" } else { "built-in" };
        let found = r.files.iter().filter(|f| f.found.is_some()).count();
        let by_hash = r.files.iter().filter(|f| f.found.as_ref().is_some_and(|l| l.by == FoundBy::BlobHash)).count();
        let hashed = if by_hash > 0 { format!(", {by_hash} by blob hash") } else { String::new() };
        println!("{:<30} {:<8} {:<9} {found} of {} found{hashed}", r.category, kind, status, r.files.len());
        if let Some(p) = &r.problem {
            println!("    {p}");
        }
        for f in r.files.iter().filter(|f| f.found.as_ref().is_some_and(|l| l.by == FoundBy::BlobHash)) {
            if let Some(l) = &f.found {
                println!("    {} -> {} (by blob hash)", f.file, l.path.display());
            }
        }
    }
    println!();
    let cache = look.cache();
    match &cache.dir {
        Some(dir) => println!("cache: {} (entries read from it: {}, made from the files: {}{})", dir.display(), cache.read, cache.made, cache.problem.as_ref().map_or(String::new(), |p| format!("; not kept: {p}"))),
        None => println!("cache: off ({} is `off`, or no home folder)", vifo_scenes::look::CACHE_VAR),
    }
    println!("look: {}", look.label());
    Ok(())
}
