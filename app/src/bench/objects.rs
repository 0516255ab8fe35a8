//! `bench --sweep objects`: the city on N x N blocks for each of `--city-blocks`
//! (`builtin:city:N`), each method along the city's streets, so a user sees how each method's
//! culling (CPU and GPU) and shadow pass grow with the number of objects. The setting column
//! names the objects.

use render_core::frame::{FrameSettings, Method};
use render_core::scene::{CITY_BLOCKS, SceneFacts};

use super::{RunOptions, baseline, path_and_lens, print_rows, run_path, set_speed_ups, summarise};
use crate::cli::{BenchArgs, SceneArgs};
use crate::headless::Session;

pub(super) fn sweep_objects(args: &BenchArgs, methods: &[Method]) -> anyhow::Result<()> {
    if let Some(n) = args.city_blocks.iter().find(|n| !CITY_BLOCKS.contains(n)) {
        anyhow::bail!(
            "--city-blocks: {n} is outside {} to {}",
            CITY_BLOCKS.start(),
            CITY_BLOCKS.end()
        );
    }
    if args.scene.scene.is_some() {
        eprintln!(
            "note: --sweep objects builds the city of each size; the scene named is not used"
        );
    }
    let baseline = baseline(&args.baseline, methods)?;
    let mut rows = Vec::new();
    for &blocks in &args.city_blocks {
        let scene = SceneArgs {
            scene: Some(format!("builtin:city:{blocks}")),
            ..args.scene.clone()
        };
        let mut session = Session::open(&scene, &args.view)?;
        let base: FrameSettings = args.view.settings(&session.scene)?;
        let (path, template) = path_and_lens(&session, args.path.as_deref(), &args.view)?;
        let facts = SceneFacts::from(&session.scene);
        let setting = format!("{} objects", facts.objects);
        eprintln!(
            "city of {blocks} x {blocks} blocks: {} objects, {} triangles",
            facts.objects, facts.triangles
        );
        let first = rows.len();
        for &method in methods {
            let reports = run_path(
                &mut session,
                (&path, &template),
                &FrameSettings { method, ..base },
                &RunOptions::from(args),
                &mut |_| {},
            )?;
            rows.push(summarise(&setting, method.name(), &reports));
        }
        set_speed_ups(&mut rows[first..], baseline.name());
    }
    print_rows(&rows, baseline.name(), args)
}
