//! `rtlab diff`: agreement, regions, the term fit and the mistake search, on the scenes of
//! tests/diff (not the ones the mistakes were written against, tests/mistakes).

use crate::common::{path, rtlab, stderr, tmp};
use rtlab::diff::{self, report, terms::TermKind, Options};
use rtlab::mistakes::{Mistake, Mistakes};
use rtlab::scene::{RenderSettings, Scene};

fn load(name: &str) -> Scene {
    Scene::load(&path(&format!("tests/diff/{name}.json"))).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The bytes `render` writes for the scene under `settings`.
fn image(scene: &Scene, settings: &RenderSettings) -> image::RgbImage {
    rtlab::sampling::render(scene, settings, false, None)
        .image
        .to_rgb8_for(settings)
}

fn diff_with(scene: &Scene, yours: &image::RgbImage, opts: &Options) -> diff::Report {
    let expected = image(scene, &scene.render);
    diff::diff(scene, &expected, yours, opts).unwrap()
}

#[test]
fn own_render_is_same_with_exit_0() {
    let png = tmp("diff-own.png");
    let o = rtlab(&[
        "render",
        "tests/diff/shading.json",
        "-q",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rtlab(&[
        "diff",
        "tests/diff/shading.json",
        png.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["verdict"], "same");
    assert_eq!(v["metrics"]["diff_percent"], 0.0);
    assert!(v["metrics"]["psnr"].is_null());
    assert_eq!(v["regions"].as_array().unwrap().len(), 0);
    // Against itself as --reference too.
    let p = png.to_str().unwrap();
    let o = rtlab(&["diff", "tests/diff/shading.json", p, "--reference", p]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("same:"));
}

#[test]
fn a_different_image_exits_1_with_regions_terms_and_a_figure() {
    let (yours, fig) = (tmp("diff-noshadow.png"), tmp("diff-fig.png"));
    let o = rtlab(&[
        "render",
        "tests/diff/occlusion.json",
        "--no-shadows",
        "-q",
        "-o",
        yours.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rtlab(&[
        "diff",
        "tests/diff/occlusion.json",
        yours.to_str().unwrap(),
        "--format",
        "json",
        "-o",
        fig.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["verdict"], "different");
    let r = &v["regions"][0];
    for key in [
        "bbox",
        "pixels",
        "objects",
        "mean_difference",
        "pixel",
        "explain",
        "terms",
        "mistakes",
    ] {
        assert!(!r[key].is_null(), "region has {key}: {r}");
    }
    // Missing shadows: yours is brighter, by the shadow term, exactly.
    assert!(r["mean_difference"][0].as_f64().unwrap() > 0.0);
    let t = &r["terms"][0];
    assert_eq!(t["term"], "shadow", "{r}");
    assert!(
        (t["coefficient"].as_f64().unwrap() - 1.0).abs() < 0.05,
        "{t}"
    );
    assert!(t["explained"].as_f64().unwrap() > 0.9, "{t}");
    let img = image::open(&fig).unwrap();
    assert!(
        img.width() > 3 * 128 && img.height() > 96,
        "{}×{}",
        img.width(),
        img.height()
    );

    // The printed explain command shows the expected colour of the representative pixel.
    let cmd = r["explain"].as_str().unwrap();
    let args: Vec<&str> = cmd
        .split_whitespace()
        .skip(1)
        .chain(["--format", "json"])
        .collect();
    let o = rtlab(&args);
    assert!(o.status.success(), "{cmd}: {}", stderr(&o));
    let e: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let (x, y) = (
        r["pixel"][0].as_u64().unwrap() as u32,
        r["pixel"][1].as_u64().unwrap() as u32,
    );
    let scene = load("occlusion");
    let expected = image(&scene, &scene.render);
    let want: Vec<u64> = expected
        .get_pixel(x, y)
        .0
        .iter()
        .map(|&b| b as u64)
        .collect();
    let got: Vec<u64> = e["encoded"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b.as_u64().unwrap())
        .collect();
    assert_eq!(got, want);
}

#[test]
fn region_pixels_are_traced_as_render_traces_them() {
    // Any filter reaching neighbours, the adaptive sampler: a few pixels alone give the
    // render's bytes.
    for (filter, sampler, spp) in [
        ("tent", "jittered", 4),
        ("mitchell", "center", 1),
        ("box", "adaptive", 16),
    ] {
        let mut scene = load("mirror");
        let r = &mut scene.render;
        r.filter = rtlab::scene::FilterKind::parse(filter).unwrap();
        r.sampler = rtlab::scene::SamplerKind::parse(sampler).unwrap();
        r.spp = spp;
        let full = image(&scene, &scene.render);
        let pixels = [(0, 0), (64, 50), (127, 95), (30, 70)];
        let some = diff::pixels::bytes(&scene, &scene.render, &pixels);
        for (p, b) in pixels.iter().zip(some) {
            assert_eq!(full.get_pixel(p.0, p.1).0, b, "{filter} {sampler} {p:?}");
        }
    }
}

/// Renders with one switch of the settings changed and fits the difference by terms.
fn terms_of(
    scene: &Scene,
    change: impl Fn(&mut RenderSettings),
) -> Vec<(TermKind, Option<String>, f64, f64)> {
    let mut s = scene.render.clone();
    change(&mut s);
    let rep = diff_with(
        scene,
        &image(scene, &s),
        &Options {
            mistake_pixels: 0,
            ..Options::default()
        },
    );
    let g = &rep.regions[0];
    g.fit
        .terms
        .iter()
        .map(|t| {
            (
                t.term.kind,
                diff::terms::light_name(scene, t.term),
                t.coefficient,
                t.explained,
            )
        })
        .collect()
}

#[test]
fn terms_with_a_known_answer() {
    let scene = load("shading");
    // No specular anywhere: −1 × the specular of every light.
    let t = terms_of(&scene, |s| s.specular = false);
    assert_eq!(t[0].0, TermKind::Specular, "{t:?}");
    assert!((t[0].2 + 1.0).abs() < 0.1 && t[0].3 > 0.8, "{t:?}");
    // No ambient: −1 × ambient.
    let t = terms_of(&scene, |s| s.ambient = false);
    assert_eq!(t[0].0, TermKind::Ambient, "{t:?}");
    assert!((t[0].2 + 1.0).abs() < 0.1 && t[0].3 > 0.8, "{t:?}");
    // No reflections: −1 × reflected.
    let mirror = load("mirror");
    let t = terms_of(&mirror, |s| s.reflections = false);
    assert_eq!(t[0].0, TermKind::Reflected, "{t:?}");
    assert!((t[0].2 + 1.0).abs() < 0.15 && t[0].3 > 0.7, "{t:?}");
    // The Intersect stage lit with its point and spot lights: +1 × the ignored lights.
    let mut spot = load("spot");
    spot.render.directional_only = true;
    spot.render.shadows = false;
    let t = terms_of(&spot, |s| {
        s.mistakes = Mistakes::one(Mistake::IntersectPointLights)
    });
    assert_eq!(t[0].0, TermKind::Ignored, "{t:?}");
    assert!((t[0].2 - 1.0).abs() < 0.1 && t[0].3 > 0.8, "{t:?}");
    // One light's specular gone (its material's specular 0 on the ball): the fit names it.
    let mut dull = load("shading");
    let gold = dull.objects.iter().position(|o| o.name == "ball").unwrap();
    let m = dull.objects[gold].material;
    let expected = image(&dull, &dull.render);
    dull.materials[m].specular = glam::DVec3::ZERO;
    let yours = image(&dull, &dull.render);
    let scene = load("shading");
    let rep = diff::diff(
        &scene,
        &expected,
        &yours,
        &Options {
            mistake_pixels: 0,
            ..Options::default()
        },
    )
    .unwrap();
    let g = &rep.regions[0];
    assert_eq!(g.objects[0].name, "ball");
    let first = &g.fit.terms[0];
    assert_eq!(first.term.kind, TermKind::Specular, "{:?}", g.fit);
    assert!((first.coefficient + 1.0).abs() < 0.1, "{:?}", g.fit);
    let says = diff::terms::sentence(&scene, first);
    assert!(
        says.contains("−1.0 × specular") && says.contains("highlights are missing"),
        "{says}"
    );
}

/// Where each mistake shows (scene, shadows off, tolerance, the Intersect stage).
struct Case {
    scene: &'static str,
    no_shadows: bool,
    tolerance: u8,
    intersect: bool,
}

fn case(m: Mistake) -> Case {
    use Mistake::*;
    let at = |scene| Case {
        scene,
        no_shadows: false,
        tolerance: 2,
        intersect: false,
    };
    match m {
        NDotLUnclamped | SpecularBehindLight => Case {
            no_shadows: true,
            ..at("backlit")
        },
        RoundBytes => Case {
            tolerance: 0,
            ..at("shading")
        },
        IntersectPointLights | IntersectShadows => Case {
            intersect: true,
            ..at("spot")
        },
        ReflectionAcne | RecursionUnclamped | ReflectionWithoutKs | ReflectSign => at("mirror"),
        ObjectSpaceT | ShadowBeyondLight | ShadowRayUnnormalized => at("occlusion"),
        RefractionEtaInverted => at("glass"),
        AmbientTimesLight => at("solids"),
        ConeNormal | CapRadius => at("solids"),
        SpotLinearFalloff | SpotFullAngle => at("spot"),
        TextureVFlipped | TextureUMirrored | TextureTimesDiffuse | TextureOffByOne => {
            at("textured")
        }
        _ => at("shading"),
    }
}

fn diagnose(c: &Case, mistakes: Mistakes) -> (diff::Report, Scene) {
    let mut scene = load(c.scene);
    scene.render.shadows &= !c.no_shadows;
    if c.intersect {
        scene.render.directional_only = true;
        scene.render.shadows = false;
    }
    let mut s = scene.render.clone();
    s.mistakes = mistakes;
    let yours = image(&scene, &s);
    let opts = Options {
        tolerance: c.tolerance,
        max_percent: 0.0,
        ..Options::default()
    };
    (diff_with(&scene, &yours, &opts), scene)
}

#[test]
fn every_mistake_is_diagnosed_first() {
    let mut wrong = Vec::new();
    for &m in Mistake::ALL {
        let c = case(m);
        let (rep, scene) = diagnose(&c, Mistakes::one(m));
        assert!(!rep.same, "{m} does not show on {}", c.scene);
        let d = report::diagnosis(&scene, &rep);
        let first = d.first().map(|d| d.0.join(" + ")).unwrap_or_default();
        if first != m.name() {
            wrong.push(format!("{m} on {}: diagnosed {first:?} ({d:?})", c.scene));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn two_mistakes_at_once_are_both_found() {
    for (a, b) in [
        (Mistake::BlinnPhong, Mistake::NormalNotNormalized),
        (Mistake::ShadowAcne, Mistake::SrgbGamma),
        (Mistake::ReflectSign, Mistake::NoAttenuation),
    ] {
        let c = Case {
            scene: "shading",
            no_shadows: false,
            tolerance: 2,
            intersect: false,
        };
        let (rep, scene) = diagnose(&c, Mistakes::one(a).with(b));
        let d = report::diagnosis(&scene, &rep);
        let named: Vec<&str> = d.iter().take(3).flat_map(|d| d.0.iter().copied()).collect();
        assert!(
            named.contains(&a.name()) && named.contains(&b.name()),
            "{a} + {b}: {d:?}"
        );
    }
}

#[test]
fn bad_inputs_get_clear_errors_and_status_2() {
    let scene = "tests/diff/solids.json";
    let small = tmp("diff-small.png");
    let o = rtlab(&[
        "render",
        scene,
        "--width",
        "64",
        "--height",
        "48",
        "-q",
        "-o",
        small.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let o = rtlab(&["diff", scene, small.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("64×48") && e.contains("128×96"), "{e}");

    let write = |name: &str, img: image::DynamicImage| {
        let p = tmp(name);
        img.save(&p).unwrap();
        p
    };
    let cases = [
        (
            write(
                "diff-grey.png",
                image::DynamicImage::ImageLuma8(image::GrayImage::new(128, 96)),
            ),
            "grey",
        ),
        (
            write(
                "diff-16.png",
                image::DynamicImage::ImageRgb16(image::ImageBuffer::new(128, 96)),
            ),
            "16-bit",
        ),
        (
            write(
                "diff-alpha.png",
                image::DynamicImage::ImageRgba8(image::RgbaImage::new(128, 96)),
            ),
            "alpha",
        ),
        (path("tests/diff/solids.json"), "not an image"),
        (tmp("diff-missing.png"), "no such file"),
    ];
    for (p, says) in cases {
        let o = rtlab(&["diff", scene, p.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{says}");
        let e = stderr(&o);
        assert!(
            e.contains(says) && e.contains(p.file_name().unwrap().to_str().unwrap()),
            "{e}"
        );
    }
    let ok = tmp("diff-ok.png");
    assert!(rtlab(&["render", scene, "-q", "-o", ok.to_str().unwrap()])
        .status
        .success());
    let o = rtlab(&[
        "diff",
        scene,
        ok.to_str().unwrap(),
        "--reference",
        small.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("64×48"), "{}", stderr(&o));
    for (args, says) in [
        (vec!["--format", "yaml"], "--format"),
        (vec!["--max-percent", "150"], "--max-percent"),
        (vec!["-o", "/tmp/fig.jpg"], ".jpg"),
        (vec!["--mistake", "shadow-akne"], "shadow-acne"),
    ] {
        let mut a = vec!["diff", scene, ok.to_str().unwrap()];
        a.extend(args);
        let o = rtlab(&a);
        assert_eq!(o.status.code(), Some(2), "{a:?}");
        assert!(stderr(&o).contains(says), "{a:?}: {}", stderr(&o));
    }
}
