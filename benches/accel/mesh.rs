//! One mesh: rounds of Embree's harness and of rtlab's passes, alternating, and their medians.

use crate::camera::HarnessCamera;
use crate::embree::run_embree;
use crate::inputs::mesh_scene;
use crate::passes::{build_seconds, bundle_pass, camera_pass, mesh_only_seconds, peak_memory_mib};
use crate::render::{render_mrays_counting, render_parts, render_view};
use crate::shadow::{shadow_bundle_pass, shadow_pass, shadow_verdicts};
use crate::{median, H, W};
use rtlab::shapes::Shape;
use std::path::Path;
use std::time::Instant;

pub struct MeshRow {
    pub name: String,
    pub triangles: usize,
    pub load_s: f64,
    pub explain_ms: f64,
    pub build_ms: f64,
    pub camera: f64,
    pub bundle: f64,
    /// The renderer's own trace time for the same view (generation, traversal, shading of
    /// a diffuse material without lights, film): single rays and bundles.
    pub render: f64,
    pub render_bundle: f64,
    /// The single-ray render again, counting as `--stats` does; and the bundled one.
    pub render_stats: f64,
    pub render_bundle_stats: f64,
    /// Seconds of the bundled render's own camera rays: made; made and walked.
    pub parts: (f64, f64),
    pub mesh_only: f64,
    pub shadow: f64,
    /// The same shadow rays in 4×4 bundles (`Accel::occluded_bundle`).
    pub shadow_bundle: f64,
    pub peak_mib: Option<f64>,
    pub bytes_per_tri: f64,
    pub hits: u64,
    pub sum_t: f64,
    pub occluded: (u64, u64),
    pub embree: Option<EmbreeSummary>,
    /// Each round's own ratios to Embree's run of that round (the rounds where it ran).
    pub paired: Vec<Paired>,
}

/// One round's ratios of rtlab to Embree, both timed in that round: the machine's load,
/// which drifts over minutes, is then common to both sides of each ratio.
pub struct Paired {
    /// Camera bundles / `rtcIntersect1`, and / `rtcIntersect16`.
    pub bundle_x1: f64,
    pub bundle_x16: f64,
    /// Shadow bundles / `rtcOccluded1`.
    pub shadow_x1: f64,
    /// The bundled render's trace / `rtcIntersect1`.
    pub render_x1: f64,
}

pub struct EmbreeSummary {
    pub build_ms: f64,
    pub camera: f64,
    pub packet8: f64,
    pub packet16: f64,
    pub shadow: f64,
    pub peak_mib: f64,
    pub hits: u64,
    pub sum_t: f64,
    pub occluded: (u64, u64),
    pub pixels_differ: usize,
}

/// rtlab's numbers of one pass, or their medians over a round's passes, or over the rounds.
#[derive(Clone, Copy)]
struct Round {
    /// Milliseconds to build the mesh's BVH.
    build: f64,
    /// Mrays/s of camera rays through the scene, one at a time.
    camera: f64,
    /// Mrays/s of the same camera rays in 4×4 bundles.
    bundle: f64,
    /// Mrays/s of the same camera rays straight into the mesh's BVH.
    mesh_only: f64,
    /// Mrays/s of shadow rays from the camera hits, one at a time.
    shadow: f64,
    /// Mrays/s of the same shadow rays in 4×4 bundles.
    shadow_bundle: f64,
    /// Mrays/s of `rtlab render`'s trace time, single rays.
    render: f64,
    /// Mrays/s of `rtlab render`'s trace time, bundles.
    render_bundle: f64,
    /// `render`, counting as `--stats` does.
    render_stats: f64,
    /// `render_bundle`, counting as `--stats` does.
    render_bundle_stats: f64,
    /// Seconds to make the bundled render's camera rays.
    made: f64,
    /// Seconds to make them and walk them to their hits.
    walked: f64,
}

impl Round {
    /// Each number's median over `all`, number by number.
    fn median(all: &[Round]) -> Round {
        macro_rules! medians {
            ($($field:ident),*) => {
                Round { $($field: median(all.iter().map(|r| r.$field).collect())),* }
            };
        }
        medians!(
            build,
            camera,
            bundle,
            mesh_only,
            shadow,
            shadow_bundle,
            render,
            render_bundle,
            render_stats,
            render_bundle_stats,
            made,
            walked
        )
    }
}

pub fn bench_mesh(
    name: &str,
    obj: &Path,
    (runs, passes): (usize, usize),
    pool: &rayon::ThreadPool,
    embree: Option<&Path>,
    tmp: &Path,
) -> MeshRow {
    println!("== {name} ({})", obj.display());
    let t0 = Instant::now();
    let scene = pool.install(|| mesh_scene(obj, tmp));
    let load_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let e = rtlab::cli::explain::explain(&scene, scene.camera.width / 2, scene.camera.height / 2);
    let explain_ms = t1.elapsed().as_secs_f64() * 1e3;
    std::hint::black_box(e);
    let Shape::Mesh(mesh) = &scene.objects[0].shape else {
        unreachable!()
    };
    let triangles = mesh.faces.len();
    let bytes_per_tri = (mesh.accel_bytes()
        + mesh.faces.len() * 12
        + (mesh.positions.len() + mesh.normals.len()) * 24
        + mesh.uvs.len() * 16) as f64
        / triangles as f64;
    let cam = HarnessCamera::new(&scene);
    let ppm = tmp.join(format!("{name}.ppm"));
    let (mut eb, mut ec, mut es, mut em) = (vec![], vec![], vec![], vec![]);
    let (mut e8, mut e16) = (vec![], vec![]);
    let mut rounds: Vec<Round> = Vec::with_capacity(runs);
    let view = render_view(obj, &cam, tmp);
    let mut last_embree = None;
    let mut last = None;
    let mut paired = Vec::new();
    let mut single_verdicts = None;
    for round in 0..runs {
        // Did Embree's harness run in this round (its lists then end with this round's)?
        let mut embree_ran = false;
        if let Some(bin) = embree {
            if let Some(e) = run_embree(bin, obj, &ppm, "single,packet8,packet16,shadow", passes) {
                embree_ran = true;
                eb.push(e.build_ms);
                ec.push(e.single);
                e8.push(e.packet8);
                e16.push(e.packet16);
                es.push(e.shadow);
                em.push(
                    run_embree(bin, obj, &ppm, "single,shadow", 1)
                        .map_or(e.peak_mib, |s| s.peak_mib),
                );
                last_embree = Some(e);
            } else if round == 0 {
                println!("  Embree harness failed on this mesh");
            }
        }
        // Each of rtlab's numbers in the round is the median of `passes` passes, taken as the
        // harness takes its `--runs`: every measurement once, then all of them again.
        let mut taken: Vec<Round> = Vec::with_capacity(passes);
        let mut found = None;
        for _ in 0..passes {
            let speed = |seconds: f64| (W * H) as f64 / seconds / 1e6;
            let build = build_seconds(&scene, pool) * 1e3;
            let pass = camera_pass(&scene, &cam, pool);
            let camera = speed(pass.seconds);
            let (secs, rays, occ) = shadow_pass(&scene, &cam, &pass, pool);
            let shadow = rays as f64 / secs / 1e6;
            let (secs, verdicts) = shadow_bundle_pass(&scene, &cam, &pass, pool);
            let shadow_bundle = rays as f64 / secs / 1e6;
            // The single rays' verdicts, found once (the first round), checked every pass.
            let single =
                single_verdicts.get_or_insert_with(|| shadow_verdicts(&scene, &cam, &pass));
            assert!(
                &verdicts == single,
                "{name}: the shadow bundles found other verdicts than single rays"
            );
            let mesh_only = speed(mesh_only_seconds(&scene, &cam, pool));
            let (seconds, bundled) = bundle_pass(&scene, &cam, pool);
            assert!(
                bundled == pass.t,
                "{name}: the bundles found other hits than single rays"
            );
            use rtlab::accel::Traversal::{Bundle, Single};
            taken.push(Round {
                build,
                camera,
                shadow,
                shadow_bundle,
                mesh_only,
                bundle: speed(seconds),
                render: render_mrays_counting(&view, Single, false, pool),
                render_bundle: render_mrays_counting(&view, Bundle, false, pool),
                made: render_parts(&view, pool, false),
                walked: render_parts(&view, pool, true),
                render_stats: render_mrays_counting(&view, Single, true, pool),
                render_bundle_stats: render_mrays_counting(&view, Bundle, true, pool),
            });
            found = Some((pass, rays, occ));
        }
        let r = Round::median(&taken);
        println!(
            "  round {}: build {:.1} ms, camera {:.2} Mrays/s (bundles {:.2}, render {:.2} / {:.2}), shadow {:.2} Mrays/s{}",
            round + 1,
            r.build,
            r.camera,
            r.bundle,
            r.render,
            r.render_bundle,
            r.shadow,
            match (eb.last(), ec.last(), es.last()) {
                (Some(bm), Some(x), Some(y)) if embree_ran => format!(
                    "  | Embree build {bm:.1} ms, camera {x:.2}, shadow {y:.2}"
                ),
                _ => String::new(),
            }
        );
        if let (true, Some(&e1), Some(&e16), Some(&eo)) =
            (embree_ran, ec.last(), e16.last(), es.last())
        {
            paired.push(Paired {
                bundle_x1: r.bundle / e1,
                bundle_x16: r.bundle / e16,
                shadow_x1: r.shadow_bundle / eo,
                render_x1: r.render_bundle / e1,
            });
        }
        rounds.push(r);
        last = found;
    }
    let (pass, rays, occ) = last.expect("at least one round");
    let embree = last_embree.map(|e| {
        let pixels_differ = e
            .mask
            .iter()
            .zip(&pass.t)
            .filter(|(&hit, &t)| hit != (t >= 0.0))
            .count();
        EmbreeSummary {
            build_ms: median(eb),
            camera: median(ec),
            packet8: median(e8),
            packet16: median(e16),
            shadow: median(es),
            peak_mib: median(em),
            hits: e.hits,
            sum_t: e.sum_t,
            occluded: (e.shadow_rays, e.occluded),
            pixels_differ,
        }
    });
    let m = Round::median(&rounds);
    MeshRow {
        name: name.to_string(),
        triangles,
        load_s,
        explain_ms,
        build_ms: m.build,
        camera: m.camera,
        bundle: m.bundle,
        render: m.render,
        render_bundle: m.render_bundle,
        render_stats: m.render_stats,
        render_bundle_stats: m.render_bundle_stats,
        parts: (m.made, m.walked),
        mesh_only: m.mesh_only,
        shadow: m.shadow,
        shadow_bundle: m.shadow_bundle,
        peak_mib: peak_memory_mib(obj),
        bytes_per_tri,
        hits: pass.hits,
        sum_t: pass.sum_t,
        occluded: (rays, occ),
        embree,
        paired,
    }
}
