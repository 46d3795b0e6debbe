//! Unit tests of the POV-Ray reader: the language (tokens, expressions,
//! directives, includes) and what the scene is built as.

use glam::DVec3;

use super::camera::CameraSpec;
use super::lex::{At, Tok, tokens};
use super::object::poly_terms;
use super::parse::Parser;
use super::value::Value;
use crate::error::Error;
use crate::lights::{Light, Shadowing};
use crate::scene::{LoadOptions, Scene};

/// A scene file with `text` in a folder of its own (kept while the guard lives).
fn file(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.pov");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// A parser that has read all of `text`'s statements (expressions are read
/// by the test through `#declare`).
fn read(text: &str) -> Parser {
    let (_dir, path) = file(text);
    let mut p = Parser::new(&path, &[], (800, 600)).unwrap();
    while p.peek().unwrap().is_some() {
        p.next().unwrap();
    }
    p
}

fn float(p: &Parser, name: &str) -> f64 {
    match p.symbol(name) {
        Some(Value::Float(v)) => *v,
        other => panic!("{name} is {other:?}"),
    }
}

fn vector(p: &Parser, name: &str) -> Vec<f64> {
    match p.symbol(name) {
        Some(Value::Vector(v)) => v.clone(),
        other => panic!("{name} is {other:?}"),
    }
}

fn load(text: &str) -> Result<Scene, Error> {
    let (_dir, path) = file(text);
    Scene::load_with(&path, &LoadOptions::default())
}

const VIEW: &str = "camera { location <0, 0, -5> look_at <0, 0, 0> }\n";

#[test]
fn tokens_know_their_line_and_column_and_comments_nest() {
    let t = tokens("a /* x /* y */ z */ 1.5e2\n  #declare // c\n<.5").unwrap();
    let kinds: Vec<&Tok> = t.iter().map(|t| &t.tok).collect();
    assert_eq!(
        kinds,
        [
            &Tok::Word("a".into()),
            &Tok::Number(150.0),
            &Tok::Directive("declare".into()),
            &Tok::Punct('<'),
            &Tok::Number(0.5),
        ]
    );
    assert_eq!(t[2].at, At { line: 2, column: 3 });
    assert_eq!(t[4].at, At { line: 3, column: 2 });
    let open = tokens("a\n  /* never closed").unwrap_err();
    assert_eq!(open.at, At { line: 2, column: 3 });
}

#[test]
fn expressions_follow_povray_precedence_and_promotion() {
    let p = read(
        "#declare A = 1 + 2 * 3 - 4 / 2;\n\
         #declare B = <1, 2, 3> * 2 + 1;\n\
         #declare C = -x + 2*y;\n\
         #declare D = (1 < 2) & (3 >= 3) & !(1 = 2);\n\
         #declare E = sqrt(16) + pow(2, 3) + max(1, 5, 3) + abs(-1);\n\
         #declare F = vlength(<3, 4, 0>) + vdot(x, <7, 1, 1>);\n\
         #declare G = <1, 2, 3>.y + image_width / image_height;\n\
         #declare H = (2 > 1 ? 10 : 20);\n\
         #declare I = pi;",
    );
    assert_eq!(float(&p, "A"), 5.0);
    assert_eq!(vector(&p, "B"), [3.0, 5.0, 7.0]);
    assert_eq!(vector(&p, "C"), [-1.0, 2.0, 0.0]);
    assert_eq!(float(&p, "D"), 1.0);
    assert_eq!(float(&p, "E"), 4.0 + 8.0 + 5.0 + 1.0);
    assert_eq!(float(&p, "F"), 5.0 + 7.0);
    assert_eq!(float(&p, "G"), 2.0 + 800.0 / 600.0);
    assert_eq!(float(&p, "H"), 10.0);
    assert_eq!(float(&p, "I"), std::f64::consts::PI);
}

#[test]
fn colours_have_five_components() {
    let p = read(
        "#declare R = rgb <1, 0, 0>;\n\
         #declare G = color red 0.5 green 1 filter 0.25;\n\
         #declare C = rgbf 1;\n\
         #declare D = R * 0.5;\n\
         #declare T = rgbt <0.1, 0.2, 0.3, 0.4>;",
    );
    assert_eq!(vector(&p, "R"), [1.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(vector(&p, "G"), [0.5, 1.0, 0.0, 0.25, 0.0]);
    assert_eq!(vector(&p, "C"), [1.0, 1.0, 1.0, 1.0, 0.0]);
    assert_eq!(vector(&p, "D"), [0.5, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(vector(&p, "T"), [0.1, 0.2, 0.3, 0.0, 0.4]);
}

/// `.gray` weighs red, green and blue as POV-Ray 3.7 does (0.297, 0.589,
/// 0.114; incdemo/sort.pov sorts colours by it), `.grey` too; a number is
/// a grey colour of itself.
#[test]
fn gray_weighs_a_colours_three_components() {
    let p = read(
        "#declare A = rgb <1, 0, 0>;\n\
         #declare R = A.gray;\n\
         #declare G = (rgb <0, 1, 0>).grey;\n\
         #declare M = (color rgb <0.2, 0.4, 0.6> filter 0.9).gray;\n\
         #declare F = (0.5).gray;",
    );
    assert_eq!(float(&p, "R"), 0.297);
    assert_eq!(float(&p, "G"), 0.589);
    assert!((float(&p, "M") - (0.297 * 0.2 + 0.589 * 0.4 + 0.114 * 0.6)).abs() < 1e-15);
    assert!((float(&p, "F") - 0.5).abs() < 1e-15);
    let (_dir, path) = file("#declare V = <1, 2>;\n#declare W = V.gray;");
    let err = Parser::new(&path, &[], (800, 600))
        .and_then(|mut p| {
            while p.peek()?.is_some() {
                p.next()?;
            }
            Ok(())
        })
        .unwrap_err()
        .to_string();
    assert!(err.contains("t.pov:2:") && err.contains("`.gray`"), "{err}");
}

/// `vaxis_rotate(A, B, F)` turns A about the axis B by F degrees: about x,
/// y or z it is `vrotate` by F on that axis, as POV-Ray's documentation
/// says, and a point on the axis stays.
#[test]
fn vaxis_rotate_turns_about_an_axis_as_vrotate_does() {
    let p = read(
        "#declare X = vaxis_rotate(<1, 2, 3>, x, 30);\n\
         #declare VX = vrotate(<1, 2, 3>, <30, 0, 0>);\n\
         #declare Y = vaxis_rotate(<1, 2, 3>, <0, 2, 0>, -75);\n\
         #declare VY = vrotate(<1, 2, 3>, <0, -75, 0>);\n\
         #declare Z = vaxis_rotate(<1, 2, 3>, z, 120);\n\
         #declare VZ = vrotate(<1, 2, 3>, <0, 0, 120>);\n\
         #declare On = vaxis_rotate(<2, 2, 2>, <1, 1, 1>, 77);\n\
         #declare Q = vaxis_rotate(x, <1, 1, 1>, 120);",
    );
    let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| (a - b).abs() < 1e-12);
    for (a, b) in [("X", "VX"), ("Y", "VY"), ("Z", "VZ")] {
        assert!(
            close(&vector(&p, a), &vector(&p, b)),
            "{a} {:?} {b} {:?}",
            vector(&p, a),
            vector(&p, b)
        );
    }
    assert!(close(&vector(&p, "On"), &[2.0, 2.0, 2.0]));
    // A third of a turn about the diagonal takes x to y.
    assert!(
        close(&vector(&p, "Q"), &[0.0, 1.0, 0.0]),
        "{:?}",
        vector(&p, "Q")
    );
}

/// A `#` that no directive follows is passed over, as POV-Ray passes it
/// over (language/image_size.pov has one before a closing brace), and a
/// macro's name after `#` calls the macro; a directive after `#` still
/// runs, with spaces between them.
#[test]
fn a_hash_without_a_directive_is_passed_over() {
    let p = read(
        "#declare A = 1;#\n\
         #macro Twice(V) (2 * V) #end\n\
         #declare B = #Twice(3);\n\
         #   declare C = <1, 2, 3>#;",
    );
    assert_eq!(float(&p, "A"), 1.0);
    assert_eq!(float(&p, "B"), 6.0);
    assert_eq!(vector(&p, "C"), [1.0, 2.0, 3.0]);
    let scene = load(&format!(
        "{VIEW}sphere {{ 0, 1 pigment {{ rgb 1 }} #\n}}\nlight_source {{ <0, 5, -5> rgb 1 }}"
    ))
    .unwrap();
    assert_eq!(scene.shapes.len(), 1);
}

#[test]
fn conditionals_take_one_branch_and_macros_are_skipped_whole() {
    let p = read(
        "#declare A = 1;\n\
         #if (A > 0) #declare B = 1; #else #declare B = 2; #end\n\
         #if (A < 0) #declare C = 1; #elseif (A = 1) #declare C = 3; #else #declare C = 2; #end\n\
         #ifndef (Guard) #declare Guard = 1; #declare D = 4; #end\n\
         #ifdef (Nothing) #declare E = 1; #end\n\
         #macro M(a) #if (a) sphere { 0, 1 } #end #while (0) #end #end\n\
         #declare F = 5;",
    );
    assert_eq!(float(&p, "B"), 1.0);
    assert_eq!(float(&p, "C"), 3.0);
    assert_eq!(float(&p, "D"), 4.0);
    assert!(p.symbol("E").is_none());
    assert!(matches!(p.symbol("M"), Some(Value::Macro(_))));
    assert_eq!(float(&p, "F"), 5.0);
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
}

#[test]
fn an_if_without_end_is_an_error_at_its_line() {
    let (_dir, path) = file("#declare A = 1;\n#if (A)\n#declare B = 2;\n");
    let mut p = Parser::new(&path, &[], (800, 600)).unwrap();
    let e = loop {
        match p.next() {
            Ok(_) => {}
            Err(e) => break e,
        }
    };
    assert!(e.to_string().contains("ends inside an `#if`"), "{e}");
}

#[test]
fn poly_coefficients_are_in_povrays_monomial_order() {
    // The torus of POV-Ray's quartic sample (major √40, minor √12, about y).
    let c = [
        1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 0.0, -104.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 56.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -104.0, 0.0,
        784.0,
    ];
    let poly = poly_terms(4, &c);
    let torus = |p: [f64; 3]| {
        let [x, y, z] = p;
        let s = x * x + y * y + z * z + 40.0 - 12.0;
        s * s - 160.0 * (x * x + z * z)
    };
    for p in [
        [1.0, 2.0, 3.0],
        [-0.5, 0.25, 7.0],
        [6.0, 0.0, 0.0],
        [0.0, -3.0, 1.0],
    ] {
        assert!((poly.eval(p) - torus(p)).abs() < 1e-9, "{p:?}");
    }
    // A point on the tube's outer equator is on the surface.
    assert!(poly.eval([40f64.sqrt() + 12f64.sqrt(), 0.0, 0.0]).abs() < 1e-9);
    assert_eq!(poly.degree(), 4);
}

#[test]
fn the_camera_resolves_as_povray_does() {
    // POV-Ray's defaults, looking down +z: right along +x (left-handed).
    let spec = CameraSpec {
        location: DVec3::new(0.0, 0.0, -10.0),
        look_at: Some(DVec3::ZERO),
        right: DVec3::new(4.0 / 3.0, 0.0, 0.0),
        angle: Some(90.0),
        ..CameraSpec::default()
    };
    let c = spec.resolve().unwrap();
    // angle 90: the direction's length is half the right vector's.
    assert!((c.direction - DVec3::new(0.0, 0.0, 2.0 / 3.0)).length() < 1e-12);
    assert!((c.right - DVec3::new(4.0 / 3.0, 0.0, 0.0)).length() < 1e-12);
    assert!((c.up - DVec3::Y).length() < 1e-12);
    // Looking along +x instead: right turns to −z, keeping the handedness.
    let side = CameraSpec {
        look_at: Some(DVec3::new(10.0, 0.0, -10.0)),
        ..spec.clone()
    };
    let c = side.resolve().unwrap();
    assert!(
        (c.right - DVec3::new(0.0, 0.0, -4.0 / 3.0)).length() < 1e-12,
        "{:?}",
        c.right
    );
    // A right-handed camera (right = −x) stays right-handed.
    let mirrored = CameraSpec {
        right: DVec3::new(-4.0 / 3.0, 0.0, 0.0),
        ..spec.clone()
    };
    let c = mirrored.resolve().unwrap();
    assert!((c.right - DVec3::new(-4.0 / 3.0, 0.0, 0.0)).length() < 1e-12);
    // Without look_at, the direction stays as given (POV-Ray's sample witch.pov).
    let skew = CameraSpec {
        direction: DVec3::new(0.0, 0.1, 1.5),
        ..CameraSpec::default()
    };
    assert_eq!(skew.resolve().unwrap().direction, DVec3::new(0.0, 0.1, 1.5));
    let nowhere = CameraSpec {
        look_at: Some(DVec3::ZERO),
        ..CameraSpec::default()
    };
    assert!(nowhere.resolve().is_err());
    // Straight down, along the sky: the right vector given stays, and up is
    // direction × right (+z here, POV-Ray's view from above: its sample
    // optics.pov).
    let above = CameraSpec {
        location: DVec3::new(0.0, 18.0, 0.0),
        ..spec.clone()
    };
    assert!(above.sky_along_view() && !spec.sky_along_view());
    let c = above.resolve().unwrap();
    assert!((c.direction - DVec3::new(0.0, -2.0 / 3.0, 0.0)).length() < 1e-12);
    assert!((c.right - DVec3::new(4.0 / 3.0, 0.0, 0.0)).length() < 1e-12);
    assert!((c.up - DVec3::Z).length() < 1e-12, "{:?}", c.up);
    // With the right vector along the view too, nothing is left to see by.
    let blind = CameraSpec {
        right: DVec3::new(0.0, -1.0, 0.0),
        ..above
    };
    assert!(blind.resolve().is_err());
}

#[test]
fn povray_37s_gamma_rules_decide_the_colour_space() {
    use crate::scene::WorkingGamma::{Linear, Power, Srgb};
    let gamma = |header: &str| {
        let scene = load(&format!("{header}\n{VIEW}sphere {{ 0, 1 }}")).unwrap();
        scene.render.working_gamma
    };
    // Without assumed_gamma: off for a scene older than 3.7 (the last
    // #version counts), 1 for a 3.7 scene.
    assert_eq!(gamma("#version 3.6;"), Srgb);
    assert_eq!(gamma("#version 3.5; #version 3.7;"), Linear);
    assert_eq!(gamma(""), Linear);
    assert_eq!(
        gamma("#version 3.6; global_settings { assumed_gamma 2.2 }"),
        Power(2.2)
    );
    assert_eq!(gamma("global_settings { assumed_gamma 1.0 }"), Linear);
    assert_eq!(gamma("global_settings { assumed_gamma srgb }"), Srgb);
    // POV-Ray keeps the first.
    assert_eq!(
        gamma("global_settings { assumed_gamma 1.5 } global_settings { assumed_gamma 2 }"),
        Power(1.5)
    );
    // Not a gamma: linear, with a warning, never a failed load.
    assert_eq!(gamma("global_settings { assumed_gamma -1 }"), Linear);
    // `version` reads back what #version set.
    let p = read("#version 3.5;\n#declare V = version;");
    assert_eq!(float(&p, "V"), 3.5);
}

#[test]
fn working_gamma_decodes_to_linear_light() {
    use crate::scene::WorkingGamma;
    let v = glam::Vec3::new(0.5, 0.0, 1.0);
    assert_eq!(WorkingGamma::Linear.to_linear(v), v);
    assert_eq!(
        WorkingGamma::Power(2.0).to_linear(v),
        glam::Vec3::new(0.25, 0.0, 1.0)
    );
    let srgb = WorkingGamma::Srgb.to_linear(v);
    assert!((srgb.x - 0.2140).abs() < 1e-4 && srgb.y == 0.0 && (srgb.z - 1.0).abs() < 1e-6);
    // Rounding below zero stays light, not NaN.
    assert_eq!(
        WorkingGamma::Power(2.2).to_linear(glam::Vec3::splat(-1e-9)),
        glam::Vec3::ZERO
    );
}

#[test]
fn an_objects_interior_is_every_part_that_has_none() {
    // iortest.pov's idiom: one declared union of glass, placed again with
    // another `interior` each time. POV-Ray gives the wrapper's interior to
    // every part without one of its own, down the tree.
    let scene = load(&format!(
        "{VIEW}#declare Thing = union {{\n\
           sphere {{ <-2, 0, 0>, 1 }}\n\
           union {{ sphere {{ <0, 0, 0>, 1 }} sphere {{ <2, 0, 0>, 1 interior {{ ior 1.2 }} }} }}\n\
         }}\n\
         object {{ Thing interior {{ ior 1.5 }} pigment {{ rgbf <1, 1, 1, 0.9> }} }}\n\
         object {{ Thing pigment {{ rgbf <1, 1, 1, 0.9> }} translate 3*y }}"
    ))
    .unwrap();
    let iors: Vec<f32> = scene
        .shapes
        .iter()
        .map(|s| scene.materials[s.material as usize].ior)
        .collect();
    assert_eq!(iors, [1.5, 1.5, 1.2, 1.0, 1.0, 1.2]);
}

#[test]
fn an_interiors_fade_reaches_the_material() {
    // glass.inc's idiom: a declared interior, then one built on it.
    let scene = load(&format!(
        "{VIEW}#declare I = interior {{ ior 1.5 fade_distance 2 fade_power 1001 }}\n\
         sphere {{ 0, 1 pigment {{ rgbf <1, 1, 1, 0.9> }} interior {{ I fade_color <1, 0.5, 0> }} }}\n\
         sphere {{ 2*x, 1 pigment {{ rgbf <1, 1, 1, 0.9> }} interior {{ ior 1.3 fade_power 2 }} }}"
    ))
    .unwrap();
    let fades: Vec<_> = scene
        .shapes
        .iter()
        .map(|s| scene.materials[s.material as usize].finish.fade)
        .collect();
    let colour = crate::math::Vec3::new(1.0, 0.5, 0.0);
    // No distance, no fade, as in POV-Ray.
    assert_eq!(
        fades,
        [crate::shading::InteriorFade::new(2.0, 1001.0, colour), None]
    );
    let fade = fades[0].unwrap();
    // Exponential: the red channel (colour 1) keeps all, the others fade.
    let left = fade.share(2.0);
    assert_eq!(left.x, 1.0);
    assert!((left.y - (-0.5f32).exp()).abs() < 1e-6 && (left.z - (-1f32).exp()).abs() < 1e-6);
    // The shadow rule: a power of 0 fades what is seen by half, not shadows.
    let flat = crate::shading::InteriorFade::new(1.0, 0.0, crate::math::Vec3::ZERO).unwrap();
    assert_eq!((flat.share(5.0).x, flat.shadow_share(5.0).x), (0.5, 1.0));
}

#[test]
fn fogs_are_read_with_povrays_defaults_and_rules() {
    let scene = load(&format!(
        "{VIEW}fog {{ distance 20 color rgbf <0.5, 0.6, 0.7, 0.2> }}\n\
         fog {{ fog_type 2 distance 4 color rgb 1 fog_offset 1 fog_alt 2 up x rotate z*90 }}\n\
         fog {{ distance 0 color rgb 1 }}\n\
         #declare Wheat = rgb <0.96, 0.87, 0.7>;\n\
         fog {{ 8 Wheat * 0.5 turbulence 0.3 octaves 4 }}"
    ))
    .unwrap();
    // A fog of distance 0 draws nothing in POV-Ray: left out.
    assert_eq!(scene.fogs.len(), 3);
    let f = &scene.fogs[0];
    assert_eq!((f.distance, f.filter, f.transmit), (20.0, 0.2, 0.0));
    assert_eq!(f.colour.to_array(), [0.5, 0.6, 0.7]);
    assert!(f.ground.is_none());
    // The up vector turns with the fog's rotation: x by 90° about z is y.
    let g = scene.fogs[1].ground.unwrap();
    assert_eq!((g.offset, g.alt), (1.0, 2.0));
    assert!((g.up - glam::DVec3::Y).length() < 1e-12, "{:?}", g.up);
    // A bare number is the distance (with POV-Ray's warning); turbulence
    // is left out with a warning naming it.
    assert_eq!(scene.fogs[2].distance, 8.0);
    // A declared colour stands without `color`, as in lights/circular.pov.
    assert_eq!(scene.fogs[2].colour.to_array(), [0.48, 0.435, 0.35]);
    let warnings = scene.warnings.join("\n");
    assert!(warnings.contains("should follow `distance`"), "{warnings}");
    assert!(
        warnings.contains("`turbulence`") && warnings.contains("without its turbulence"),
        "{warnings}"
    );
}

#[test]
fn a_lights_shadowing_is_read_and_its_grid_shaping_is_warned_about() {
    let scene = load(&format!(
        "{VIEW}light_source {{ <0, 5, 0> color rgb 1 shadowless media_attenuation }}\n\
         light_source {{ <0, 5, 0> color rgb 1 media_attenuation on media_interaction off }}\n\
         light_source {{ <0, 5, 0> color rgb 1 spotlight point_at 0 media_attenuation 1 }}\n\
         light_source {{ <0, 5, 0> color rgb 1 area_light x, z, 2, 2 jitter orient off }}"
    ))
    .unwrap();
    let shadowing: Vec<_> = scene.lights.iter().map(Light::shadowing).collect();
    let (plain, fogged) = (Shadowing::default(), |shadowless| Shadowing {
        shadowless,
        fogged: true,
    });
    // Four lights of the grid, none shaped: `orient off` is no warning.
    assert_eq!(
        shadowing,
        [
            fogged(true),
            plain,
            fogged(false),
            plain,
            plain,
            plain,
            plain
        ]
    );
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains(":5:") && warnings.contains("`jitter`"),
        "{warnings}"
    );
    assert!(!warnings.contains("orient"), "{warnings}");
}

#[test]
fn a_circular_area_light_is_a_disc() {
    // A 2x2 square of 5x5 lights, bent into the disc of radius 1 as
    // POV-Ray bends it: its corners come in to the circle, its middle
    // stays (0.001 of the square off the centre, POV-Ray's offset).
    let light = |circular: &str| {
        load(&format!(
            "{VIEW}light_source {{ <0, 5, 0> color rgb 1 area_light 2*x, 2*z, 5, 5 {circular} }}"
        ))
        .unwrap()
        .lights
        .iter()
        .map(|l| match l {
            Light::PovPoint { position, .. } => {
                (position.as_dvec3() - DVec3::new(0.0, 5.0, 0.0)).length()
            }
            other => panic!("{other:?}"),
        })
        .collect::<Vec<f64>>()
    };
    let (square, disc) = (light(""), light("circular"));
    assert_eq!((square.len(), disc.len()), (25, 25));
    let corner = square.iter().copied().fold(0.0, f64::max);
    assert!((corner - 2f64.sqrt()).abs() < 1e-6, "{corner}");
    // Within the unit circle about the grid's centre moved by POV-Ray's
    // offset, 0.001 of each edge (2 units): 0.002·√2 off.
    assert!(disc.iter().all(|&r| r <= 1.0 + 0.0029), "{disc:?}");
    // The corner lights lie on the circle, the middle one at the centre.
    assert!((disc[0] - 0.998).abs() < 1e-6, "{disc:?}");
    assert!(disc[12] < 0.0025, "{disc:?}");
}

#[test]
fn amounts_the_classic_material_cannot_draw_are_warned_about() {
    let scene = load(&format!(
        "{VIEW}sphere {{ 0, 1 pigment {{ rgbt <1, 1, 1, 100> }} finish {{ diffuse 1.5 ambient -1 }} }}\n\
         sphere {{ 0, 1 pigment {{ rgbft <1, 1, 1, 0.5, 0.5> }} finish {{ diffuse 1 phong 0 }} }}"
    ))
    .unwrap();
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains(":2:25: filter 0 and transmit 100"),
        "{warnings}"
    );
    assert!(
        warnings.contains("`diffuse 1.5` is outside [0, 1]: drawn as 1"),
        "{warnings}"
    );
    assert!(
        warnings.contains("`ambient -1` is outside [0, 1]: drawn as 0"),
        "{warnings}"
    );
    // The second sphere's amounts are all drawable: no warning names line 3.
    assert!(!warnings.contains(":3:"), "{warnings}");
}

#[test]
fn an_array_elements_warnings_are_given_where_it_is_used() {
    // As POV-Ray's incdemo/texture1.pov uses textures.inc's noise pigments:
    // declared, put in an array, and used by element.
    let declare = "#declare Noisy = pigment { bozo }\n\
                   #declare Pigments = array[2] { pigment { Noisy }, pigment { rgb 1 } }\n";
    let used = load(&format!(
        "{VIEW}{declare}sphere {{ 0, 1 pigment {{ Pigments[0] }} }}"
    ))
    .unwrap();
    assert!(
        used.warnings
            .iter()
            .any(|w| w.contains(":2:") && w.contains("`bozo`")),
        "{:?}",
        used.warnings
    );
    let unused = load(&format!("{VIEW}{declare}sphere {{ 0, 1 }}")).unwrap();
    assert!(
        !unused.warnings.iter().any(|w| w.contains("bozo")),
        "{:?}",
        unused.warnings
    );
}

#[test]
fn hollow_reaches_the_shape_and_a_unions_parts() {
    let scene = load(&format!(
        "{VIEW}sphere {{ 0, 1 hollow }}\n\
         sphere {{ 0, 1 hollow off }}\n\
         union {{ sphere {{ 3*x, 1 }} sphere {{ 6*x, 1 }} hollow }}\n\
         sphere {{ 0, 1 }}"
    ))
    .unwrap();
    let hollow: Vec<bool> = scene.shapes.iter().map(|s| s.hollow()).collect();
    assert_eq!(hollow, [true, false, true, true, false]);
}

#[test]
fn a_scene_builds_shapes_lights_and_povrays_settings() {
    let scene = load(&format!(
        "{VIEW}light_source {{ <0, 10, 0> color rgb <1, 0.5, 0.25> }}\n\
         sphere {{ <1, 2, 3>, 0.5 pigment {{ rgb <0.2, 0.4, 0.6> }} finish {{ phong 0.7 }} }}\n\
         background {{ color rgb 0.1 }}\nbackground {{ color rgb 0.3 }}\n\
         global_settings {{ max_trace_level 7 }}"
    ))
    .unwrap();
    assert_eq!(scene.shapes.len(), 1);
    let m = &scene.materials[scene.shapes[0].material as usize];
    assert_eq!(m.albedo.to_array(), [0.2, 0.4, 0.6]);
    assert_eq!(m.finish.phong, 0.7);
    // POV-Ray's defaults: ambient 0.1, diffuse 0.6.
    assert_eq!((m.finish.ambient, m.finish.diffuse), (0.1, 0.6));
    let pi = std::f32::consts::PI;
    assert_eq!(
        scene.lights,
        [Light::PovPoint {
            position: crate::math::Vec3::new(0.0, 10.0, 0.0),
            irradiance: crate::math::Vec3::new(pi, 0.5 * pi, 0.25 * pi),
            fade: None,
            shadowing: Default::default(),
        }]
    );
    // The later background replaces the earlier one.
    assert_eq!(scene.background.to_array(), [0.3; 3]);
    // brilliance: read, not warned about.
    assert_eq!(m.finish.brilliance, 1.0);
    assert_eq!(scene.render.max_depth, 6);
    assert_eq!(scene.render.spp, 1);
    assert_eq!(scene.render.photons.count, 0);
    assert_eq!((scene.camera.width, scene.camera.height), (800, 600));
    let import = scene.import.as_ref().unwrap();
    assert_eq!(import.read.get("sphere"), Some(&1));
    assert!(import.skipped.is_empty());
}

#[test]
fn lights_fade_from_their_centre_and_finishes_keep_their_brilliance() {
    let scene = load(&format!(
        "{VIEW}light_source {{ <0, 10, 0> color rgb 1 fade_distance 5 fade_power 2 \
         area_light x*2, z*2, 2, 2 }}
         light_source {{ <0, 10, 0> color rgb 1 fade_power 2 }}
         sphere {{ 0, 1 finish {{ brilliance 3.5 }} }}"
    ))
    .unwrap();
    let fades: Vec<_> = scene
        .lights
        .iter()
        .map(|l| match l {
            Light::PovPoint { fade, .. } => *fade,
            other => panic!("{other:?}"),
        })
        .collect();
    // Four lights of the grid, each faded from the grid's centre; the
    // second light has no distance, so it does not fade (POV-Ray's rule).
    let centre = crate::math::Vec3::new(0.0, 10.0, 0.0);
    let fade = crate::lights::Fade::new(5.0, 2.0, centre);
    assert!(fade.is_some());
    assert_eq!(fades, [fade, fade, fade, fade, None]);
    let m = &scene.materials[scene.shapes[0].material as usize];
    assert_eq!(m.finish.brilliance, 3.5);
}

#[test]
fn what_is_outside_the_subset_is_skipped_with_a_warning_naming_the_line() {
    let scene = load(&format!(
        "{VIEW}isosurface {{ function {{ x }} }}\n\
         sphere {{ 0, 1 normal {{ bumps 0.5 }} }}\n\
         rainbow {{ angle 42 width 5 }}\n"
    ))
    .unwrap();
    assert_eq!(scene.shapes.len(), 1);
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains("t.pov:2:1: `isosurface` is not supported"),
        "{warnings}"
    );
    assert!(
        warnings.contains("t.pov:3:15: `normal` is not supported"),
        "{warnings}"
    );
    assert!(
        warnings.contains("t.pov:4:1: `rainbow` is not supported"),
        "{warnings}"
    );
    let skipped = &scene.import.as_ref().unwrap().skipped;
    assert_eq!(skipped.len(), 3, "{skipped:?}");
}

#[test]
fn declarations_warn_only_where_they_are_used() {
    let quiet = load(&format!(
        "{VIEW}#declare Unused = texture {{ pigment {{ granite }} normal {{ bumps }} }}\n\
         sphere {{ 0, 1 }}"
    ))
    .unwrap();
    assert!(
        quiet.warnings.iter().all(|w| !w.contains("granite")),
        "{:?}",
        quiet.warnings
    );
    let used = load(&format!(
        "{VIEW}#declare Used = texture {{ pigment {{ granite }} }}\n\
         sphere {{ 0, 1 texture {{ Used }} }}"
    ))
    .unwrap();
    assert!(
        used.warnings.iter().any(|w| w.contains("`granite`")),
        "{:?}",
        used.warnings
    );
}

#[test]
fn a_declaration_can_use_the_one_before_it() {
    // Each declaration is made before the next directive runs: a texture
    // looks ahead for layers, and must not run `#declare B` before A exists.
    let scene = load(&format!(
        "#declare A = texture {{ pigment {{ rgb <0.2, 0.4, 0.6> }} }}\n\
         #declare B = texture {{ A scale 2 }}\n\
         #declare C = 1 #declare D = C + 1;\n\
         {VIEW}sphere {{ 0, D texture {{ B }} }}"
    ))
    .unwrap();
    assert!(
        scene.warnings.iter().all(|w| !w.contains("not supported")),
        "{:?}",
        scene.warnings
    );
    let m = &scene.materials[scene.shapes[0].material as usize];
    assert_eq!(m.albedo.to_array(), [0.2, 0.4, 0.6]);
    assert!((scene.shapes[0].bounds().max.x - 2.0).abs() < 1e-3);
}

#[test]
fn no_shadow_objects_are_seen_but_cast_no_shadow() {
    let scene = load(&format!(
        "{VIEW}union {{ sphere {{ 0, 1 }} sphere {{ 3*x, 1 }} no_shadow }}\nsphere {{ -3*x, 1 }}"
    ))
    .unwrap();
    let (o, down) = (DVec3::new(0.0, 10.0, 0.0), DVec3::new(0.0, -1.0, 0.0));
    for (i, x) in [(0, 0.0), (1, 3.0)] {
        let shape = &scene.shapes[i];
        let o = o + DVec3::new(x, 0.0, 0.0);
        assert!(shape.intersect(o, down, 0.0, f64::INFINITY).is_some());
        assert!(!shape.occluded(o, down, 0.0, f64::INFINITY));
    }
    let o = o + DVec3::new(-3.0, 0.0, 0.0);
    assert!(scene.shapes[2].occluded(o, down, 0.0, f64::INFINITY));
}

#[test]
fn syntax_errors_name_the_line_and_column() {
    let e = load(&format!("{VIEW}sphere {{ <0, 0, 0>, 1\n  box {{ 1 }}")).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains(
            "t.pov:3:3: expected a modifier of this object or `}`, found the object `box`"
        ),
        "{text}"
    );
    assert!(e.is_bad_input());
    let e = load(&format!("{VIEW}sphere {{ 0, -1 }}")).unwrap_err();
    assert!(
        e.to_string()
            .contains("t.pov:2:13: the radius must be a number > 0"),
        "{e}"
    );
    let e = load(&format!("{VIEW}sphere {{ 0, Radius }}")).unwrap_err();
    assert!(e.to_string().contains("unknown name `Radius`"), "{e}");
    let e = load("quartic { <1, 2, 3> }").unwrap_err();
    assert!(
        e.to_string().contains("takes 35 coefficients, found 3"),
        "{e}"
    );
}

#[test]
fn includes_are_found_beside_the_file_then_in_the_given_folders() {
    let dir = tempfile::tempdir().unwrap();
    let extra = tempfile::tempdir().unwrap();
    std::fs::write(extra.path().join("mine.inc"), "#declare R = 0.25;").unwrap();
    let path = dir.path().join("s.pov");
    std::fs::write(
        &path,
        format!("#include \"mine.inc\"\n{VIEW}sphere {{ 0, R }}"),
    )
    .unwrap();
    let missing = Scene::load_with(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        missing
            .to_string()
            .contains("s.pov:1:1: cannot find the include file \"mine.inc\""),
        "{missing}"
    );
    let options = LoadOptions {
        pov_include: vec![extra.path().to_owned()],
        ..LoadOptions::default()
    };
    let scene = Scene::load_with(&path, &options).unwrap();
    assert_eq!(scene.shapes.len(), 1);
    assert!(scene.sources.contains(&extra.path().join("mine.inc")));
    // A file that includes itself stops at the nesting limit.
    std::fs::write(&path, "#include \"s.pov\"").unwrap();
    let e = Scene::load_with(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .contains("includes and macro calls nest deeper than 32"),
        "{e}"
    );
}

#[test]
fn a_clear_part_of_an_intersection_becomes_an_invisible_cut() {
    let scene = load(&format!(
        "{VIEW}intersection {{\n\
           sphere {{ 0, 1 pigment {{ rgb 1 }} }}\n\
           box {{ -2, <2, 0.5, 2> pigment {{ rgbf 1 }} }}\n\
         }}"
    ))
    .unwrap();
    assert_eq!(scene.shapes.len(), 1);
    // A ray down onto the top meets the sphere's inside wall below the cut
    // (the cut face, clear, is not there), at y = −1 … the far wall: t = 10 + 1.
    let shape = &scene.shapes[0];
    let hit = shape
        .intersect(
            DVec3::new(0.0, 10.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
            0.0,
            f64::INFINITY,
        )
        .unwrap();
    assert!((hit.t - 11.0).abs() < 1e-9, "{}", hit.t);
}

#[test]
fn hostile_nesting_is_refused_not_a_stack_overflow() {
    let deep = |open: &str, close: &str, n: usize| format!("{}{}", open.repeat(n), close.repeat(n));
    for text in [
        format!(
            "#declare A = {};",
            deep("(", ")", 100_000).replacen(")", "1)", 1)
        ),
        format!("#declare A = {}1;", "-".repeat(100_000)),
        format!("#declare A = {};", deep("<", ">", 100_000)),
        deep("union { ", "}", 100_000),
        // In parentheses: only there is `? :` read, as in POV-Ray.
        format!("#declare A = (1 {});", "? 1 : 1 ".repeat(100_000)),
    ] {
        let e = load(&text).unwrap_err();
        assert!(
            e.to_string().contains("nests deeper than 256 levels"),
            "{e}"
        );
    }
    // 100 parentheses are read (each is two levels: an expression in a term).
    let ok = format!(
        "#declare A = {}1{};\n{VIEW}sphere {{ 0, A }}",
        "(".repeat(100),
        ")".repeat(100)
    );
    assert!(load(&ok).is_ok());
}

/// Pieces of POV-Ray's language, for scenes made at random.
const PIECES: &[&str] = &[
    "sphere",
    "box",
    "quartic",
    "poly",
    "union",
    "intersection",
    "difference",
    "merge",
    "object",
    "camera",
    "light_source",
    "plane",
    "torus",
    "cone",
    "cylinder",
    "disc",
    "mesh",
    "mesh2",
    "triangle",
    "texture",
    "pigment",
    "finish",
    "checker",
    "rgb",
    "color",
    "red",
    "scale",
    "rotate",
    "translate",
    "matrix",
    "clipped_by",
    "bounded_by",
    "inverse",
    "open",
    "#declare",
    "#local",
    "#if",
    "#else",
    "#end",
    "#macro",
    "#while",
    "#switch",
    "#case",
    "(1)",
    "#for",
    "#break",
    "I",
    "(I, 0, 2)",
    "(I < 3)",
    "#declare I = I + 1;",
    "#include",
    "#version",
    "#default",
    "A",
    "x",
    "y",
    "pi",
    "sqrt",
    "(",
    ")",
    "{",
    "}",
    "<",
    ">",
    ",",
    ";",
    "=",
    "+",
    "-",
    "*",
    "/",
    "?",
    ":",
    "0",
    "1",
    "2.5",
    "-1",
    "1e300",
    "\"s\"",
    "/*",
    "*/",
    "//",
    "look_at",
    "location",
    "angle",
    "global_settings",
    "max_trace_level",
    "background",
    "vertex_vectors",
    "face_indices",
    "area_light",
    "quadric",
    "interior",
    "ior",
    "\n",
];

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]

    /// Whatever the text, reading it ends in a scene or an error: never a panic.
    #[test]
    fn random_scenes_never_panic(picks in proptest::collection::vec(0..PIECES.len(), 0..60)) {
        let text: Vec<&str> = picks.iter().map(|&i| PIECES[i]).collect();
        let _ = load(&text.join(" "));
    }
}

#[test]
fn a_plane_alone_is_cut_by_the_world_box_and_hit() {
    let scene = load(&format!("{VIEW}plane {{ y, -1 }}")).unwrap();
    let shape = &scene.shapes[0];
    let d = DVec3::new(0.0, -4.0, 3.0) / 5.0;
    let hit = shape
        .intersect(DVec3::new(0.0, 3.0, -6.0), d, 0.0, f64::INFINITY)
        .unwrap();
    assert!((hit.t - 5.0).abs() < 1e-9, "{}", hit.t);
    // Far away too: 10⁶ units out.
    let far = DVec3::new(0.0, -1.0, 1e6 / 4.0).normalize();
    let hit = shape
        .intersect(DVec3::new(0.0, 3.0, -6.0), far, 0.0, f64::INFINITY)
        .unwrap();
    let p = DVec3::new(0.0, 3.0, -6.0) + hit.t * far;
    assert!((p.y + 1.0).abs() < 1e-6, "{p}");
}

/// A scene using much of the subset, for mutations.
const RICH: &str = "#version 3.7;\n#declare R = 0.5;\n#declare T = texture { pigment { checker rgb 1 rgb 0 scale 0.5 } finish { phong 0.5 reflection { 0.1 0.5 fresnel } } }\n\
camera { location <0, 2, -6> look_at <0, 0, 0> angle 50 right x*image_width/image_height }\n\
light_source { <10, 10, -10> color rgb 1 area_light x, y, 2, 2 }\n\
#if (R > 0) plane { y, -1 texture { T } } #else sphere { 0, 1 } #end\n\
intersection { quartic { <1,0,0,0,2,0,0,2,0,-104,0,0,0,0,0,0,0,0,0,0,1,0,0,2,0,56,0,0,0,0,1,0,-104,0,784> } sphere { 0, 10 pigment { rgbf 1 } } bounded_by { sphere { 0, 11 } } scale 0.1 }\n\
difference { box { -1, 1 } cylinder { -2*x, 2*x, R open } clipped_by { plane { z, 0.5 } } rotate <10, 20, 30> translate 2*x }\n\
mesh2 { vertex_vectors { 3, <0,0,0>, <1,0,0>, <0,1,0> } face_indices { 1, <0,1,2> } }\n";

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(1000))]

    /// A real scene with tokens cut out, doubled or swapped: a scene or an
    /// error, never a panic.
    #[test]
    fn mutated_scenes_never_panic(
        cuts in proptest::collection::vec((0usize..200, 0usize..3), 1..6),
    ) {
        let mut words: Vec<&str> = RICH.split_inclusive([' ', ',', '{', '}', '<', '>', '\n']).collect();
        for (at, how) in cuts {
            let i = at % words.len();
            match how {
                0 => { words.remove(i); }
                1 => { let w = words[i]; words.insert(i, w); }
                _ => { let j = (i * 7 + 3) % words.len(); words.swap(i, j); }
            }
            if words.is_empty() {
                break;
            }
        }
        let _ = load(&words.concat());
    }
}

#[test]
fn the_rich_scene_reads() {
    let scene = load(RICH).unwrap();
    assert_eq!(scene.shapes.len(), 3);
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.lights.len(), 4);
}

#[test]
fn only_uncoloured_light_makes_a_part_clear() {
    use super::object::clear;
    use super::texture::Pigment;
    // POV-Ray's Clear (rgbf 1), and transmit, which is never coloured.
    assert!(clear(&Pigment::Colour([1.0, 1.0, 1.0, 1.0, 0.0])));
    assert!(clear(&Pigment::Colour([0.2, 0.0, 0.0, 0.0, 1.0])));
    // A red filter lets only red through: a surface, not a cut.
    assert!(!clear(&Pigment::Colour([1.0, 0.0, 0.0, 1.0, 0.0])));
    assert!(!clear(&Pigment::Colour([1.0, 1.0, 1.0, 0.5, 0.4])));
}

/// POV-Ray reads `<` and `>` as comparisons only inside parentheses, so a
/// vector may follow another without a comma, and commas between a
/// vector's numbers are optional (checked against POV-Ray 3.7's `#debug`).
#[test]
fn commas_are_optional_and_comparisons_need_parentheses() {
    let p = read(
        "#declare A = <1 2 3>;\n\
         #declare B = <1 -2 3>;\n\
         #declare C = <1, 2, 3,>;\n\
         #declare H = 7; #declare D = <1 H 3>;\n\
         #declare E = (1 < 2);\n\
         #declare F = (2 > 1 ? 5 : 6);",
    );
    assert_eq!(vector(&p, "A"), [1.0, 2.0, 3.0]);
    assert_eq!(vector(&p, "B"), [-1.0, 3.0]);
    assert_eq!(vector(&p, "C"), [1.0, 2.0, 3.0]);
    assert_eq!(vector(&p, "D"), [1.0, 7.0, 3.0]);
    assert_eq!(float(&p, "E"), 1.0);
    assert_eq!(float(&p, "F"), 5.0);
    // Two corners without a comma between them make a box, not a comparison.
    let scene = load(&format!("{VIEW}box {{ <-1, -1, -1> <1, 1, 1> }}")).unwrap();
    assert_eq!(scene.shapes.len(), 1);
}

#[test]
fn a_matrix_takes_its_twelve_numbers() {
    let scene = load(&format!(
        "{VIEW}sphere {{ 0, 1 matrix <1, 0, 0, 0, 1, 0, 0, 0, 1, 3, 0, 0> }}"
    ))
    .unwrap();
    let b = scene.shapes[0].bounds();
    assert!(
        (b.min.x - 2.0).abs() < 1e-3 && (b.max.x - 4.0).abs() < 1e-3,
        "{b:?}"
    );
    let err = load(&format!("{VIEW}sphere {{ 0, 1 matrix <1, 0, 0> }}")).unwrap_err();
    assert!(err.to_string().contains("12 numbers"), "{err}");
}

/// Macros run: a call stands for its body wherever it is (a statement,
/// an object, a declared value, a texture, an expression), its parameters
/// and `#local`s local to it. A macro whose body needs what the reader
/// does not run (`vturbulence`) is skipped with a warning wherever it
/// stands, as arrays are.
#[test]
fn macros_run_where_called_and_those_that_cannot_are_skipped_with_a_warning() {
    let scene = load(&format!(
        "{VIEW}#macro Thing(a, b) sphere {{ a, b }} #end\n\
         #macro Paint(p) texture {{ pigment {{ p }} }} #end\n\
         #macro Twice(v) #local w = v * 2; w #end\n\
         #declare a = 7;\n\
         Thing(<1, 2, 3>, 1)\n\
         object {{ Thing(<0, 5, 0>, 1) }}\n\
         #declare Made = Thing(<0, 10, 0>, Twice(1));\n\
         object {{ Made }}\n\
         sphere {{ <0, 20, 0>, a Paint(rgb <1, 0, 0>) }}\n\
         #macro Jitter(p) sphere {{ p + vturbulence(1, 2, 0.5, p), 1 }} #end\n\
         Jitter(0)\n\
         object {{ Jitter(0) }}\n"
    ))
    .unwrap();
    // Centre and radius of each sphere, from its bounds (rounded outwards
    // to f32).
    let got: Vec<[f64; 4]> = scene
        .shapes
        .iter()
        .map(|s| {
            let b = s.bounds();
            let c = ((b.min + b.max) * 0.5).as_dvec3();
            [c.x, c.y, c.z, f64::from(b.max.x - b.min.x) * 0.5]
        })
        .collect();
    let want = [
        [1.0, 2.0, 3.0, 1.0],
        [0.0, 5.0, 0.0, 1.0],
        [0.0, 10.0, 0.0, 2.0],
        [0.0, 20.0, 0.0, 7.0],
    ];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert!(
            g.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-5),
            "{got:?}"
        );
    }
    let red = &scene.materials[scene.shapes[3].material as usize];
    assert_eq!(red.albedo.to_array(), [1.0, 0.0, 0.0]);
    let warnings = scene.warnings.join("\n");
    for place in ["t.pov:12:1: `Jitter`", "t.pov:13:10: `Jitter`"] {
        assert!(warnings.contains(place), "{place} in {warnings}");
    }
    // Each says what stops it.
    assert_eq!(
        warnings
            .matches("a macro is not run (it uses `vturbulence`)")
            .count(),
        2,
        "{warnings}"
    );
    // A call with the wrong number of arguments is an error at the call.
    let e = load(&format!(
        "{VIEW}#macro Paint(p) texture {{ pigment {{ p }} }} #end\n\
         sphere {{ 0, 1 Paint(rgb 1, 2) }}"
    ))
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("t.pov:3:15: the macro `Paint` takes 1 argument(s), found 2"),
        "{e}"
    );
}

/// A camera kind outside the subset is read as a perspective one; an angle
/// of 180 degrees or more, which a perspective camera cannot have, is then
/// left out with a warning instead of stopping the read.
#[test]
fn a_wide_camera_of_another_kind_falls_back_to_the_default_angle() {
    let scene = load(
        "camera { fisheye location <0, 0, -5> look_at 0 angle 360 }\n\
         camera { spherical location <0, 0, -5> look_at 0 angle 360, 180 }\n\
         sphere { 0, 1 }",
    )
    .unwrap();
    let warnings = scene.warnings.join("\n");
    assert!(warnings.contains("t.pov:1:48: angle 360"), "{warnings}");
    assert!(warnings.contains("`fisheye`"), "{warnings}");
    // A perspective camera with such an angle stays an error, as in POV-Ray.
    let err =
        load("camera { location <0, 0, -5> look_at 0 angle 200 }\nsphere { 0, 1 }").unwrap_err();
    assert!(err.to_string().contains("below 180"), "{err}");
}

/// A pigment map's entries may be declared pigments (their colour counts)
/// or patterns of their own (left out, with a warning), as in POV-Ray's
/// pigment samples.
#[test]
fn pigment_map_entries_take_declared_pigments_and_skip_patterns() {
    let scene = load(&format!(
        "{VIEW}light_source {{ <0, 0, -5> rgb 1 }}\n\
         #declare Red = pigment {{ rgb <1, 0, 0> }}\n\
         sphere {{ 0, 1 pigment {{ gradient y pigment_map {{\n\
           [0 Red]\n\
           [0.5 gradient z color_map {{ [0 rgb 0] [1 rgb 1] }} translate -z]\n\
           [1, rgb <0, 0, 1>] }} }} }}\n"
    ))
    .unwrap();
    assert_eq!(scene.shapes.len(), 1);
    let albedo = scene.materials[scene.shapes[0].material as usize].albedo;
    // The mean of the two colours read: red and blue.
    assert!(
        (albedo - crate::math::Vec3::new(0.5, 0.0, 0.5))
            .abs()
            .max_element()
            < 1e-6,
        "{albedo}"
    );
    let warnings = scene.warnings.join("\n");
    assert!(warnings.contains("t.pov:6:6: `gradient`"), "{warnings}");
}

#[test]
fn spotlights_cylinders_and_parallel_lights_take_povrays_defaults_and_order() {
    use crate::lights::Beam;
    use crate::math::Vec3;
    let scene = load(&format!(
        "{VIEW}light_source {{ <0, 5, 0>, rgb 1 spotlight point_at <0, 5, 3> translate x }}\n\
         light_source {{ <0, 5, 0>, rgb 1 spotlight radius 10 falloff 20 tightness 4 }}\n\
         light_source {{ <0, 5, 0>, rgb 1 cylinder point_at 0 }}\n\
         light_source {{ <0, 5, 0>, rgb 1 parallel point_at <0, 5, -2> }}\n\
         light_source {{ <0, 5, 0>, rgb 1 }}\n"
    ))
    .unwrap();
    let cos = |d: f32| d.to_radians().cos();
    let beams: Vec<_> = scene
        .lights
        .iter()
        .map(|l| match l {
            Light::PovBeam(l) => Some((l.position, l.direction, l.beam, l.parallel)),
            _ => None,
        })
        .collect();
    // POV-Ray's spotlight: radius 30, falloff 45, tightness 0; the point_at
    // moves with the light.
    assert_eq!(
        beams[0],
        Some((
            Vec3::new(1.0, 5.0, 0.0),
            Vec3::Z,
            Beam::Spot {
                cos_radius: cos(30.0),
                cos_falloff: cos(45.0),
                tightness: 0.0
            },
            false
        ))
    );
    // Without point_at: POV-Ray's default aim at <0, 0, 1>.
    let (_, direction, beam, _) = beams[1].unwrap();
    assert!((direction - Vec3::new(0.0, -5.0, 1.0).normalize()).length() < 1e-6);
    assert_eq!(
        beam,
        Beam::Spot {
            cos_radius: cos(10.0),
            cos_falloff: cos(20.0),
            tightness: 4.0
        }
    );
    // A cylinder is parallel, radius 0.75 and falloff 1 (distances).
    assert_eq!(
        beams[2],
        Some((
            Vec3::new(0.0, 5.0, 0.0),
            -Vec3::Y,
            Beam::Cylinder {
                radius: 0.75,
                falloff: 1.0,
                tightness: 0.0
            },
            true
        ))
    );
    assert_eq!(
        beams[3],
        Some((Vec3::new(0.0, 5.0, 0.0), -Vec3::Z, Beam::Round, true))
    );
    assert_eq!(beams[4], None, "a plain point light stays unfading");
    // A spotlight's keyword before `spotlight` is POV-Ray's parse error too.
    for item in ["radius 10", "falloff 3", "tightness 2", "point_at 0"] {
        let e = load(&format!(
            "{VIEW}light_source {{ 0, rgb 1\n {item} spotlight }}"
        ))
        .unwrap_err();
        assert!(e.is_bad_input());
        let word = item.split(' ').next().unwrap();
        assert!(
            e.to_string().contains(&format!(
                "t.pov:3:2: `{word}` cannot be used with a standard light source"
            )),
            "{e}"
        );
    }
}

/// The first hit of the ray o + t·d on the scene's first shape: its t and
/// its unit normal.
fn first_hit(scene: &Scene, o: DVec3, d: DVec3) -> Option<(f64, DVec3)> {
    scene.shapes[0]
        .intersect(o, d, 0.0, f64::INFINITY)
        .map(|hit| (hit.t, hit.normal.normalize()))
}

/// That a hit is there, at t with the unit normal n.
fn assert_hit(got: Option<(f64, DVec3)>, t: f64, n: DVec3) {
    let (gt, gn) = got.unwrap_or_else(|| panic!("no hit, expected t = {t}"));
    assert!(
        (gt - t).abs() < 1e-9 && (gn - n).length() < 1e-9,
        "{got:?}, expected ({t}, {n})"
    );
}

#[test]
fn csg_unbounded_as_a_whole_is_cut_by_the_world_box() {
    // Down the y axis from y = 10 at (x, z).
    let down =
        |scene: &Scene, x: f64, z: f64| first_hit(scene, DVec3::new(x, 10.0, z), DVec3::NEG_Y);
    let close = |got, t: f64, ny: f64| assert_hit(got, t, DVec3::new(0.0, ny, 0.0));
    // A floor merged with a ball on it (POV-Ray's idiom: a union holding a
    // plane): the ball's top, and the floor beside it.
    let merged = load(&format!(
        "{VIEW}merge {{ plane {{ y, -1 }} sphere {{ 0, 1 }} }}"
    ))
    .unwrap();
    close(down(&merged, 0.0, 0.0), 9.0, 1.0);
    close(down(&merged, 3.0, 0.0), 11.0, 1.0);
    // Ground with a channel cut out (the first child of a difference
    // unbounded): the channel's floor, and the ground beside it.
    let channel = load(&format!(
        "{VIEW}difference {{ plane {{ y, 0 }} box {{ <-1, -2, -5>, <1, 0.1, 20> }} }}"
    ))
    .unwrap();
    close(down(&channel, 0.0, 0.0), 12.0, 1.0);
    close(down(&channel, 3.0, 0.0), 10.0, 1.0);
    // A cube made of six half-spaces (shapes2.inc's polyhedra are made so):
    // bounded, though no child is.
    let cube = load(&format!(
        "{VIEW}intersection {{ plane {{ y, 1 }} plane {{ -y, 1 }} plane {{ x, 1 }} \
         plane {{ -x, 1 }} plane {{ z, 1 }} plane {{ -z, 1 }} }}"
    ))
    .unwrap();
    close(down(&cube, 0.5, 0.3), 9.0, 1.0);
    assert_eq!(down(&cube, 3.0, 0.0), None);
}

#[test]
fn a_triangle_alone_is_a_mesh_of_one_placed_and_textured_as_any_object() {
    let scene = load(&format!(
        "{VIEW}triangle {{ <-1, 0, -1>, <1, 0, -1>, <0, 0, 1> pigment {{ rgb <1, 0, 0> }} translate y }}\n\
         smooth_triangle {{ <-1, 0, 0>, <-1, 1, 0>, <1, 0, 0>, <1, 1, 0>, <0, 1, 0>, <1, 1, 0> scale <2, 1, 1> }}\n\
         mesh {{ triangle {{ <0, 0, 0>, <1, 0, 0>, <0, 1, 0> }} }}"
    ))
    .unwrap();
    let [flat, smooth, plain] = &scene.meshes[..] else {
        panic!("{} meshes", scene.meshes.len());
    };
    assert_eq!(flat.triangles, [[0, 1, 2]]);
    let y: Vec<f32> = flat.positions.iter().map(|p| p.y).collect();
    assert_eq!(y, [1.0, 1.0, 1.0]);
    assert!(flat.normals.is_empty() && plain.normals.is_empty());
    let material = &scene.materials[flat.materials[0] as usize];
    assert_ne!(material, &scene.materials[plain.materials[0] as usize]);
    // A smooth triangle keeps its corners' normals, mapped as normals are:
    // <±1, 1, 0> under scale <2, 1, 1> leans towards y.
    assert_eq!(smooth.normals.len(), 3);
    for (n, x) in smooth.normals.iter().zip([-0.5, 0.5, 0.5]) {
        let expected = crate::math::Vec3::new(x, 1.0, 0.0).normalize();
        assert!((*n - expected).length() < 1e-6, "{n} against {expected}");
    }
}

#[test]
fn an_open_tube_in_csg_keeps_its_inside_and_shows_no_caps() {
    let (first, close) = (first_hit, assert_hit);
    // A box less an open tube through it (POV-Ray's Inside test ignores
    // `open`): the hole goes through the box's faces, and a ray down the
    // axis meets nothing; beside the hole, the face is there.
    let drilled = load(&format!(
        "{VIEW}difference {{ box {{ -2, 2 }} cylinder {{ <-3, 0, 0>, <3, 0, 0>, 1 open }} }}"
    ))
    .unwrap();
    let from_left = DVec3::new(-10.0, 0.0, 0.0);
    assert_eq!(first(&drilled, from_left, DVec3::X), None);
    close(
        first(&drilled, DVec3::new(-10.0, 1.5, 0.0), DVec3::X),
        8.0,
        DVec3::NEG_X,
    );
    // Across the axis: the box's face, then the tube's inner wall.
    close(
        first(&drilled, DVec3::new(0.0, 0.0, -10.0), DVec3::Z),
        8.0,
        DVec3::NEG_Z,
    );
    close(
        first(&drilled, DVec3::new(0.0, 0.0, -1.5), DVec3::Z),
        0.5,
        DVec3::Z,
    );
    // A ball cut to a short open tube: its ends are open (the caps are not
    // seen), its wall is.
    let ring = load(&format!(
        "{VIEW}intersection {{ sphere {{ 0, 1.5 }} cylinder {{ <0, 0, -1>, <0, 0, 1>, 1 open }} }}"
    ))
    .unwrap();
    assert_eq!(first(&ring, DVec3::new(0.0, 0.0, -10.0), DVec3::Z), None);
    close(first(&ring, from_left, DVec3::X), 9.0, DVec3::NEG_X);
}

#[test]
fn a_bounded_unions_triangles_are_drawn_beside_its_gated_rest() {
    let scene = load(&format!(
        "{VIEW}union {{ triangle {{ <-2, -1, 0>, <2, -1, 0>, <0, 2, 0> }} \
         sphere {{ <0, 0, -1>, 0.5 }} mesh {{ triangle {{ <0, 0, 1>, <1, 0, 1>, <0, 1, 1> }} }} \
         bounded_by {{ box {{ -3, 3 }} }} translate x }}"
    ))
    .unwrap();
    assert_eq!(scene.meshes.len(), 2);
    assert_eq!(
        scene.meshes[0].positions[0],
        crate::math::Vec3::new(-1.0, -1.0, 0.0)
    );
    // The sphere keeps the bound, moved with it.
    assert_eq!(scene.shapes.len(), 1);
    assert_hit(
        first_hit(&scene, DVec3::new(1.0, 0.0, -10.0), DVec3::Z),
        8.5,
        DVec3::NEG_Z,
    );
}

#[test]
fn a_mesh2s_normals_shade_it_smooth() {
    let quad = "vertex_vectors { 4, <0,0,0>, <1,0,0>, <1,1,0>, <0,1,0> }\n\
                normal_vectors { 2, <0,0,-1>, <1,0,-1> }";
    // With normal_indices: each face's corners pick their normals.
    let indexed = load(&format!(
        "{VIEW}mesh2 {{ {quad} face_indices {{ 2, <0,1,2>, <0,2,3> }} \
         normal_indices {{ 2, <0,1,1>, <0,1,0> }} }}"
    ))
    .unwrap();
    let mesh = &indexed.meshes[0];
    let (a, b) = (
        crate::math::Vec3::new(0.0, 0.0, -1.0),
        crate::math::Vec3::new(1.0, 0.0, -1.0).normalize(),
    );
    assert_eq!(mesh.normals.len(), 6);
    for (got, want) in mesh.normals.iter().zip([a, b, b, a, b, a]) {
        assert!((*got - want).length() < 1e-6, "{got} against {want}");
    }
    // Without: the face's own indices pick them, and one past the list is
    // an error naming it.
    let own = load(&format!(
        "{VIEW}mesh2 {{ {quad} face_indices {{ 1, <0,1,0> }} }}"
    ))
    .unwrap();
    assert!((own.meshes[0].normals[1] - b).length() < 1e-6);
    let past = load(&format!(
        "{VIEW}mesh2 {{ {quad} face_indices {{ 1, <0,1,2> }} }}"
    ))
    .unwrap_err()
    .to_string();
    assert!(past.contains("beyond the 2 in normal_vectors"), "{past}");
}

#[test]
fn a_checker_of_textures_is_a_checker_of_their_colours() {
    let p = read(
        "#declare A = texture { pigment { rgb <1, 0, 0> } finish { phong 1 } }\n\
         #declare B = texture { pigment { rgb <0, 0, 1> } }\n\
         #declare X = texture { checker texture { A }, texture { B } scale 0.5 }\n\
         #declare Y = texture { checker texture { A } texture { pigment { checker rgb 1 rgb 0 } } }\n\
         #declare P = pigment { checker rgb <1, 0, 0> rgb <0, 0, 1> }\n",
    );
    // Another `rgb` starts the checker's second colour, as in POV-Ray (it
    // used to be read as changing the first).
    let Some(Value::Pigment(super::texture::Pigment::Checker { colours, .. })) = p.symbol("P")
    else {
        panic!("P is {:?}", p.symbol("P"));
    };
    assert_eq!(
        colours,
        &[[1.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0, 0.0]]
    );
    let Some(Value::Texture(x)) = p.symbol("X") else {
        panic!("X is {:?}", p.symbol("X"));
    };
    let super::texture::Pigment::Checker { colours, to_owner } = &x.pigment else {
        panic!("{:?}", x.pigment);
    };
    assert_eq!(
        colours,
        &[[1.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0, 0.0]]
    );
    assert_eq!(to_owner.matrix3.x_axis.x, 0.5);
    let Some(Value::Texture(a)) = p.symbol("A") else {
        panic!("A is {:?}", p.symbol("A"));
    };
    assert_eq!(x.finish, a.finish);
    // Y's second texture is patterned: Y is its first, A.
    let Some(Value::Texture(y)) = p.symbol("Y") else {
        panic!("Y is {:?}", p.symbol("Y"));
    };
    assert_eq!(**y, **a);
    // Their warnings come where they are used.
    let scene = load(&format!(
        "{VIEW}#declare A = texture {{ pigment {{ rgb 1 }} finish {{ phong 1 }} }}\n\
         sphere {{ 0, 1 texture {{ checker texture {{ A }} texture {{ pigment {{ rgb 0 }} }} }} }}\n\
         sphere {{ 0, 1 texture {{ checker texture {{ A }} texture {{ pigment {{ checker }} }} }} }}"
    ))
    .unwrap();
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains("t.pov:3:25: a checker of textures takes its first"),
        "{warnings}"
    );
    assert!(
        warnings.contains("t.pov:4:25: a checker of patterned textures"),
        "{warnings}"
    );
}

#[test]
fn a_flat_box_alone_is_the_rectangle_povray_draws() {
    let scene = load(&format!(
        "{VIEW}box {{ <-1, -1, 0>, <1, 2, 0> rotate 90*x translate y }}"
    ))
    .unwrap();
    // Turned to lie in y = 1, from x = -1 to 1 and z = -1 to 2 (rotate
    // 90*x takes +y to +z), seen from either side.
    let (t, n) = first_hit(&scene, DVec3::new(0.5, 10.0, 1.5), DVec3::NEG_Y).unwrap();
    assert!(
        (t - 9.0).abs() < 1e-9 && (n.y.abs() - 1.0).abs() < 1e-9,
        "{t} {n}"
    );
    let (t, _) = first_hit(&scene, DVec3::new(0.5, -10.0, 1.5), DVec3::Y).unwrap();
    assert!((t - 11.0).abs() < 1e-9, "{t}");
    assert_eq!(
        first_hit(&scene, DVec3::new(1.5, 10.0, 0.0), DVec3::NEG_Y),
        None
    );
    assert_eq!(
        first_hit(&scene, DVec3::new(0.0, 10.0, -1.5), DVec3::NEG_Y),
        None
    );
    // In CSG it has no inside: left out, with a warning naming why.
    let cut = load(&format!(
        "{VIEW}intersection {{ sphere {{ 0, 1 }} box {{ <-1, -1, 0>, <1, 1, 0> }} }}"
    ));
    let warnings = cut
        .map(|s| s.warnings.join("\n"))
        .unwrap_or_else(|e| e.to_string());
    assert!(warnings.contains("a flat box is left out"), "{warnings}");
}

#[test]
fn an_array_element_declared_as_a_texture_ends_at_its_brace() {
    // A texture or object element has no `;` after it (POV-Ray's
    // stackergold.pov): read to its `}`, and used where named.
    let scene = load(&format!(
        "{VIEW}#declare TG = array[2]\n\
         #declare TG[0] = texture {{ pigment {{ rgb <1, 0, 0> }} }}\n\
         #declare TG[1] = texture {{ pigment {{ rgb <0, 1, 0> }} }}\n\
         sphere {{ 0, 1 texture {{ TG[1] }} }}"
    ))
    .unwrap();
    assert_eq!(scene.shapes.len(), 1);
    let green = &scene.materials[scene.shapes[0].material as usize];
    assert_eq!(green.albedo.to_array(), [0.0, 1.0, 0.0]);
}

#[test]
fn a_two_number_vector_has_a_zero_third_component() {
    // POV-Ray 3.7 renders `translate <1, 0.5>` as `translate <1, 0.5, 0>`
    // (the same pixels), and a sphere centred on a declared <a, b>.
    let declared = load(&format!(
        "{VIEW}#declare C = <0, 2>;\nsphere {{ C, 1 translate <1, 0.5> }}"
    ))
    .unwrap();
    // Down the y axis over the centre (1, 2.5, 0): the top at y = 3.5.
    let got = first_hit(&declared, DVec3::new(1.0, 10.0, 0.0), DVec3::NEG_Y);
    assert_hit(got, 6.5, DVec3::Y);
    // Off the centre along z, the hit's height tells the centre's z: 0.
    let off = first_hit(&declared, DVec3::new(1.0, 10.0, 0.6), DVec3::NEG_Y);
    assert_hit(off, 7.5 - 0.8, DVec3::new(0.0, 0.8, 0.6));
}

#[test]
fn a_sky_sphere_is_drawn_over_any_background_before_or_after_it() {
    // POV-Ray 3.7 shows the sky_sphere wherever both are given, in either
    // order (checked on a render of each order); a later sky_sphere
    // replaces an earlier one.
    for text in [
        "sky_sphere { pigment { rgb <0.2, 0.4, 0.6> } }\nbackground { color rgb <1, 0, 0> }",
        "background { color rgb <1, 0, 0> }\nsky_sphere { pigment { rgb <0.2, 0.4, 0.6> } }",
        "sky_sphere { pigment { rgb 1 } }\nsky_sphere { pigment { rgb <0.2, 0.4, 0.6> } }",
    ] {
        let scene = load(&format!("{VIEW}{text}")).unwrap();
        assert_eq!(scene.background.to_array(), [0.2, 0.4, 0.6], "{text}");
    }
}

#[test]
fn an_object_without_a_texture_takes_the_default_in_force_where_it_is_placed() {
    // POV-Ray 3.7 draws both spheres red here (checked on a render): the
    // `#default` after the declarations applies where the objects are
    // placed; a child's own texture stays its own.
    let scene = load(&format!(
        "{VIEW}#declare A = sphere {{ <-2, 0, 0>, 1 }}\n\
         #declare B = union {{ sphere {{ <2, 0, 0>, 1 }} sphere {{ <2, 2, 0>, 0.5 pigment {{ rgb <0, 0, 1> }} }} }}\n\
         #default {{ texture {{ pigment {{ rgb <1, 0, 0> }} }} }}\n\
         object {{ A }}\nobject {{ B }}"
    ))
    .unwrap();
    let albedo = |i: usize| {
        scene.materials[scene.shapes[i].material as usize]
            .albedo
            .to_array()
    };
    let mut colours: Vec<[f32; 3]> = (0..scene.shapes.len()).map(albedo).collect();
    colours.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(colours, [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
}

#[test]
fn declared_cameras_and_skies_are_used_where_named() {
    // POV-Ray's scene templates declare their camera and sky, then name
    // them: `camera { Camera_0 }`, `sky_sphere { Sky translate … }`.
    let scene = load(
        "#declare Cam = camera { location <0, 0, -5> look_at <0, 0, 0> angle 40 }\n\
         #declare Sky = sky_sphere { pigment { rgb <0.2, 0.4, 0.6> } }\n\
         camera { Cam translate <0, 1, 0> }\n\
         sky_sphere { Sky rotate <0, 30, 0> }\n\
         sphere { <0, 1, 0>, 1 }",
    )
    .unwrap();
    let named = load(
        "camera { location <0, 1, -5> look_at <0, 1, 0> angle 40 }\n\
         sky_sphere { pigment { rgb <0.2, 0.4, 0.6> } }\nsphere { <0, 1, 0>, 1 }",
    )
    .unwrap();
    assert_eq!(scene.camera, named.camera);
    assert_eq!(scene.background.to_array(), [0.2, 0.4, 0.6]);
}

#[test]
fn a_local_in_an_include_file_holds_to_its_end_and_declare_changes_it() {
    // As POV-Ray 3.7 renders it (language/macros/local.pov, and a scene
    // written for this test): inside the include, a #declare of a name a
    // #local holds changes the local; after it, the global comes back and
    // the include's other locals are gone.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("inc.inc"),
        "#local R = 0.25;\n#declare R = 0.5;\nsphere { <-2, 0, 0>, R }\n\
         #local Gone = 1;\n#declare Kept = 0.75;",
    )
    .unwrap();
    let path = dir.path().join("s.pov");
    std::fs::write(
        &path,
        format!(
            "{VIEW}#declare R = 1;\n#include \"inc.inc\"\nsphere {{ <2, 0, 0>, R }}\n\
             #ifdef (Gone) sphere {{ <0, 5, 0>, 1 }} #end\nsphere {{ <0, -3, 0>, Kept }}"
        ),
    )
    .unwrap();
    let scene = Scene::load_with(&path, &LoadOptions::default()).unwrap();
    assert_eq!(scene.shapes.len(), 3);
    // Down each centre from y = 10: the top at y = radius (or -3 + radius).
    let top = |x: f64| {
        scene
            .shapes
            .iter()
            .filter_map(|s| s.intersect(DVec3::new(x, 10.0, 0.0), DVec3::NEG_Y, 0.0, 1e9))
            .map(|hit| 10.0 - hit.t)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    assert!((top(-2.0) - 0.5).abs() < 1e-9, "{}", top(-2.0));
    assert!((top(2.0) - 1.0).abs() < 1e-9, "{}", top(2.0));
    assert!((top(0.0) + 2.25).abs() < 1e-9, "{}", top(0.0));
}

/// The centres of a scene's spheres, in the order placed.
fn centres(scene: &Scene) -> Vec<[f64; 3]> {
    scene
        .shapes
        .iter()
        .map(|s| {
            let b = s.bounds();
            ((b.min + b.max) * 0.5).as_dvec3().to_array()
        })
        .collect()
}

/// That the scene's spheres have these centres, in order (their bounds
/// are rounded outwards to f32, hence the tolerance).
fn assert_centres(scene: &Scene, want: &[[f64; 3]]) {
    let got = centres(scene);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            g.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-5),
            "{got:?}"
        );
    }
}

/// `seed` and `rand` give POV-Ray's numbers. The expected values are what
/// POV-Ray 3.7 printed for this scene with `#debug vstr(3, P, ", ", 0,
/// 17)` in place of each sphere, to 10 decimals (the centres are read
/// back from f32 bounds). A stream is a number, so a copy of it
/// (`T`) and a macro's parameter step the same stream; a seed is cut to an
/// int (-7.6 to -7), and one outside the int range starts from -2^31.
#[test]
fn random_streams_give_povray_s_numbers() {
    let scene = load(&format!(
        "{VIEW}#declare S = seed(498961);\n#declare Z = seed(0);\n\
         #for (I, 1, 2) sphere {{ <rand(S), rand(S), rand(Z)>, 1 }} #end\n\
         #macro Next(R) rand(R) #end\n#declare T = S;\n\
         sphere {{ <Next(T), rand(seed(-7.6)), rand(seed(1e12))>, 1 }}\n"
    ))
    .unwrap();
    assert_centres(
        &scene,
        &[
            [0.5528297980, 0.8641536310, 0.0000028743],
            [0.1602201136, 0.6571043128, 0.4665636845],
            [0.9820159103, 0.0460728682, 0.5000028744],
        ],
    );
    let skipped = scene.warnings.iter().find(|w| w.contains("not supported"));
    assert!(skipped.is_none(), "{skipped:?}");
    // A number no `seed` made is not a stream: POV-Ray stops there too
    // ("Illegal random number generator").
    let e = load(&format!(
        "{VIEW}#declare S = seed(3);\nsphere {{ rand(S + 1), 1 }}"
    ))
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("t.pov:3:10: `rand(1)`: no random stream"),
        "{e}"
    );
}

/// Arrays as POV-Ray 3.7 reads them (each value below is what its
/// `#debug` printed for the same declarations): a copy by `#declare` is
/// separate, an array passed to a macro is the caller's own, an index is
/// truncated, and an element may stand wherever a value of its kind does.
#[test]
fn arrays_hold_values_as_povray_s_do() {
    let scene = load(&format!(
        "{VIEW}#declare A = array[3] {{1, 2, 3}}\n#declare B = A;\n#declare B[0] = 5;\n\
         sphere {{ <A[0], B[0], 0>, 1 }}\n\
         #macro Set(Arr) #declare Arr[1] = 9; #end\nSet(A)\nsphere {{ <A[1], 0, 0>, 1 }}\n\
         #declare M = array[2][3] {{ {{1, 2, 3}}, {{4 5, 6}}, }}\n\
         sphere {{ <M[1][2], dimension_size(M, 2), dimensions(M)>, 1 }}\n\
         sphere {{ <M[1.9][0.5], 0, 0>, 1 }}\n\
         #declare C = array[4]\n#declare C[2] = <1, 2, 3>;\nsphere {{ C[2], 1 }}\n\
         #declare Objs = array[2] {{ sphere {{ <0, 30, 0>, 1 }}, sphere {{ <0, 40, 0>, 1 }} }}\n\
         object {{ Objs[1] translate x }}\n\
         #for (I, 0, 1) object {{ Objs[I] }} #end\n\
         #if (A[2] = 3) sphere {{ <0, 50, 0>, 1 }} #end\n"
    ))
    .unwrap();
    assert_centres(
        &scene,
        &[
            [1.0, 5.0, 0.0],
            [9.0, 0.0, 0.0],
            [6.0, 3.0, 2.0],
            [4.0, 0.0, 0.0],
            [1.0, 2.0, 3.0],
            [1.0, 40.0, 0.0],
            [0.0, 30.0, 0.0],
            [0.0, 40.0, 0.0],
            [0.0, 50.0, 0.0],
        ],
    );
    let skipped = scene.warnings.iter().find(|w| w.contains("not supported"));
    assert!(skipped.is_none(), "{skipped:?}");
    // What POV-Ray refuses is an error at the place: an element never
    // declared, an index outside, an initializer short of the size, and a
    // size past the cap (hostile input, not an allocation).
    for (text, message) in [
        (
            "#declare C = array[4]\nsphere { C[1], 1 }",
            "t.pov:3:10: `C[1]` was never declared",
        ),
        (
            "#declare C = array[4] {1, 2, 3, 4}\nsphere { C[4], 1 }",
            "t.pov:3:12: index 4 is outside `C`",
        ),
        (
            "#declare C = array[3] {1, 2}",
            "this array's initializer has 2 elements, its size 3",
        ),
        ("#declare C = array[1e12]", "an array's size must be 1 to"),
        ("#declare C = array[3000][3000]", "at most 4194304 elements"),
        ("#declare X = 1;\n#declare X[0] = 2;", "`X` is not an array"),
        // A loop that makes a large array on every pass: stopped, not run
        // for minutes.
        (
            "#for (I, 1, 1000) #declare C = array[1000000] #end",
            "arrays have made or copied 16777216 elements in all",
        ),
    ] {
        let e = load(&format!("{VIEW}{text}")).unwrap_err().to_string();
        assert!(e.contains(message), "{message} not in {e}");
    }
}

#[test]
fn while_and_for_loops_run_their_bodies_as_povray_does() {
    let scene = load(&format!(
        "{VIEW}#declare I = 0;\n#while (I < 3) sphere {{ <I * 3, 0, 0>, 1 }} #declare I = I + 1; #end\n\
         #for (J, 10, 1, -4) sphere {{ <J, 5, 0>, 1 }} #end\n\
         #for (K, 0, 9) #if (K = 2) #break #end sphere {{ <K, 9, 0>, 1 }} #end\n\
         #declare N = 0;\n#while (1) #declare N = N + 1; #if (N > 1) #break #else sphere {{ <0, 20, 0>, 1 }} #end #end"
    ))
    .unwrap();
    assert_centres(
        &scene,
        &[
            [0.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [10.0, 5.0, 0.0],
            [6.0, 5.0, 0.0],
            [2.0, 5.0, 0.0],
            [0.0, 9.0, 0.0],
            [1.0, 9.0, 0.0],
            [0.0, 20.0, 0.0],
        ],
    );
    let import = scene.import.as_ref().unwrap();
    assert_eq!(import.read.get("#while"), Some(&2));
    assert_eq!(import.read.get("#for"), Some(&2));
}

#[test]
fn a_loop_that_never_ends_stops_with_an_error_at_it() {
    let e = load(&format!("{VIEW}#declare A = 1;\n#while (A > 0) #end")).unwrap_err();
    assert!(
        e.to_string()
            .contains("t.pov:3:1: loops and macro calls have gone round 1000000 times"),
        "{e}"
    );
    let e = load(&format!("{VIEW}#for (I, 0, 1, 0) #end")).unwrap_err();
    assert!(e.to_string().contains("step of 0 never ends"), "{e}");
    let e = load(&format!("{VIEW}#while (1) sphere {{ 0, 1 }}")).unwrap_err();
    assert!(e.to_string().contains("missing `#end`"), "{e}");
}

#[test]
fn a_declared_light_goes_on_in_a_light_source_naming_it() {
    // radiosity/cornell.pov's idiom: one declared light placed by a loop.
    let scene = load(&format!(
        "{VIEW}#declare L = light_source {{ <0, 10, 0> color rgb 1 }}\n\
         #for (I, 0, 1) light_source {{ L translate <I * 4, 0, 0> }} #end"
    ))
    .unwrap();
    let positions: Vec<[f32; 3]> = scene
        .lights
        .iter()
        .map(|l| match l {
            Light::PovPoint { position, .. } => position.to_array(),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(positions, [[0.0, 10.0, 0.0], [4.0, 10.0, 0.0]]);
}

#[test]
fn a_switch_runs_from_the_clause_that_matches_and_falls_through_to_a_break() {
    // POV-Ray 3.7 draws the spheres at x = -3 and 0 here (checked on a
    // render): #range (2, 3) holds 2, and the run falls through #case (4)
    // to its #break.
    let scene = load(&format!(
        "{VIEW}#declare G = 2;\n\
         #switch (G)\n\
           #case (1) sphere {{ <-6, 0, 0>, 1 }} #break\n\
           #range (2, 3) sphere {{ <-3, 0, 0>, 1 }}\n\
           #case (4) sphere {{ <0, 0, 0>, 1 }} #break\n\
           #else sphere {{ <3, 0, 0>, 1 }}\n\
         #end\n\
         #switch (7) #case (1) sphere {{ <-6, 4, 0>, 1 }} #else sphere {{ <0, 4, 0>, 1 }} #end\n\
         #switch (5) #case (1) sphere {{ <1, 1, 1>, 1 }} #end"
    ))
    .unwrap();
    assert_centres(
        &scene,
        &[[-3.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 4.0, 0.0]],
    );
    let e = load(&format!("{VIEW}#case (1) sphere {{ 0, 1 }}")).unwrap_err();
    assert!(e.to_string().contains("`#case` outside a `#switch`"), "{e}");
}

#[test]
fn a_macro_that_calls_itself_twice_over_stops_with_an_error() {
    // 2^21 calls, each well within the nesting limit: stopped at the cap on
    // loop passes and macro calls, not run for hours.
    let e = load(&format!(
        "{VIEW}#macro R(n) #if (n < 20) R(n + 1) R(n + 1) #end #end\nR(0)"
    ))
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("loops and macro calls have gone round 1000000 times"),
        "{e}"
    );
}

#[test]
fn a_local_at_a_macros_end_goes_out_of_scope_with_it() {
    // No `;` after the value: reading on to see where it ends leaves the
    // macro's body first. The local still ends with the body, as in
    // POV-Ray; a #declare there is kept.
    let p = read(
        "#macro Set(v) #declare Kept = v; #local Leak = v #end\n\
         Set(3)\n#declare After = 1;",
    );
    assert!(p.symbol("Leak").is_none());
    assert!(p.symbol("v").is_none());
    assert_eq!(float(&p, "Kept"), 3.0);
    assert_eq!(float(&p, "After"), 1.0);
}

/// A `light_group` (abyss.pov's mines) is read as the union of its
/// objects; its own lights, which POV-Ray lets light only those objects,
/// are left out with a warning instead of lighting the whole scene.
#[test]
fn a_light_group_is_a_union_of_its_objects_without_its_own_lights() {
    let scene = load(&format!(
        "{VIEW}light_source {{ <0, 10, -10> rgb 1 }}\n\
         union {{ light_group {{ sphere {{ <2, 0, 0>, 1 }} light_source {{ <0, 0, -3> rgb -4 }} \
         global_lights on }} sphere {{ <-2, 0, 0>, 1 }} }}"
    ))
    .unwrap();
    assert_eq!(scene.lights.len(), 1);
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains("t.pov:3:9: `light_group` is not supported: read as a union"),
        "{warnings}"
    );
    assert_centres(&scene, &[[2.0, 0.0, 0.0], [-2.0, 0.0, 0.0]]);
}

/// POV-Ray's orthographic camera: parallel rays along the view, each from
/// its point of the plane of right and up through the location. Given
/// neither up nor right, the view is what the perspective camera sees at
/// the look_at distance: right 1.33 and up 1 times that distance over the
/// direction's length (POV-Ray's rule; `make povray-compare`'s idioms
/// check the pixels against POV-Ray itself).
#[test]
fn an_orthographic_camera_sends_parallel_rays_over_its_view() {
    let sized = load(
        "camera { orthographic location <0, 0, -10> up 4*y right 4*x look_at 0 }\nsphere { 0, 1 }",
    )
    .unwrap();
    let plane = sized.camera.plane.unwrap();
    assert!(plane.orthographic);
    assert_eq!(
        (plane.right, plane.up),
        (DVec3::new(4.0, 0.0, 0.0), DVec3::new(0.0, 4.0, 0.0))
    );
    let frame = sized.camera.frame();
    let (corner, centre) = (frame.ray64(0.0, 0.0), frame.ray64(400.0, 300.0));
    assert_eq!(corner.dir, DVec3::Z);
    assert_eq!(centre.dir, DVec3::Z);
    assert!(
        (corner.origin - DVec3::new(-2.0, 2.0, -10.0)).length() < 1e-12,
        "{}",
        corner.origin
    );
    assert!(
        (centre.origin - DVec3::new(0.0, 0.0, -10.0)).length() < 1e-12,
        "{}",
        centre.origin
    );
    // Neither up nor right: sized at look_at, 5 away with a direction of 1.
    let at_look_at =
        load("camera { orthographic location <0, 0, -5> look_at 0 }\nsphere { 0, 1 }").unwrap();
    let plane = at_look_at.camera.plane.unwrap();
    assert!(
        (plane.right.length() - 1.33 * 5.0).abs() < 1e-12,
        "{}",
        plane.right
    );
    assert!((plane.up.length() - 5.0).abs() < 1e-12, "{}", plane.up);
    // Another kind of camera is still read as a perspective one.
    let other = load("camera { fisheye location <0, 0, -5> look_at 0 }\nsphere { 0, 1 }").unwrap();
    assert!(!other.camera.plane.unwrap().orthographic);
    assert!(
        other
            .warnings
            .iter()
            .any(|w| w.contains("`fisheye` is not supported"))
    );
}

/// A colour-mapped pattern is read into the material (its rendered colours
/// match POV-Ray's: `make povray-compare`'s pattern idioms); one with
/// turbulence, which POV-Ray draws from its noise, or with clear entries
/// in its map, stays its map's mean colour with a warning.
#[test]
fn a_mapped_pattern_is_drawn_and_turbulence_keeps_the_mean_colour() {
    let scene = load(&format!(
        "{VIEW}#declare M = color_map {{ [0 rgb <1, 0, 0>] [1 rgb <0, 0, 1>] }}\n\
         sphere {{ 0, 1 pigment {{ gradient 2*y color_map {{ M }} scale 2 }} }}\n\
         sphere {{ <3, 0, 0>, 1 pigment {{ marble turbulence 0.5 color_map {{ M }} }} }}\n\
         sphere {{ <6, 0, 0>, 1 pigment {{ gradient y color_map {{ [0 rgbt <1, 1, 1, 1>] [1 rgb 0] }} }} }}"
    ))
    .unwrap();
    let material = |i: usize| &scene.materials[scene.shapes[i].material as usize];
    let mapped = material(0).mapped.as_ref().expect("a mapped pattern");
    // The direction is normalised, as POV-Ray reads it; the scale moves the
    // pattern: at y = 1 the value is 0.5, halfway between red and blue.
    assert_eq!(mapped.kind, crate::shading::PatternKind::Gradient(DVec3::Y));
    let half = material(0).albedo_at(glam::Vec3::new(0.0, 1.0, 0.0), glam::Vec3::ZERO, None);
    assert!(
        (half - glam::Vec3::new(0.5, 0.0, 0.5)).length() < 1e-5,
        "{half}"
    );
    assert!(material(1).mapped.is_none());
    assert_eq!(material(1).albedo.to_array(), [0.5, 0.0, 0.5]);
    // Clear entries: the renderer lets one fraction through the whole
    // surface, so the map's mean stands for the pattern (half clear).
    assert!(material(2).mapped.is_none());
    assert_eq!(material(2).finish.transmit, 0.5);
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains("`turbulence` is not reproduced"),
        "{warnings}"
    );
    assert!(
        warnings.contains("filter or transmit in the colour map is not reproduced"),
        "{warnings}"
    );
}

/// A macro's argument that is a bare declared name is passed by reference,
/// as POV-Ray passes it: what the body declares its parameter to be (by
/// `#declare` or `#local`) is the name's value after the call, through a
/// macro that passes it on too; an expression is passed by value. The
/// values are what POV-Ray 3.7's `#debug` printed for the same calls.
#[test]
fn a_bare_name_is_passed_to_a_macro_by_reference() {
    let scene = load(&format!(
        "{VIEW}#macro Inc(V) #declare V = V + 1; #end\n\
         #macro IncLocal(V) #local V = V + 10; #end\n\
         #macro Set2(P, Q) #declare P = 5; #declare Q = P * 2; #end\n\
         #macro Outer(W) Inc(W) #end\n\
         #declare A = 1;\nInc(A)\nsphere {{ <A, 0, 0>, 1 }}\n\
         IncLocal(A)\nInc(A + 0)\nsphere {{ <A, 0, 0>, 1 }}\n\
         #declare X = 0; #declare Y = 0;\nSet2(X, Y)\nsphere {{ <X, Y, 0>, 1 }}\n\
         Outer(X)\nsphere {{ <X, 0, 0>, 1 }}\n"
    ))
    .unwrap();
    assert_centres(
        &scene,
        &[
            [2.0, 0.0, 0.0],
            [12.0, 0.0, 0.0],
            [5.0, 10.0, 0.0],
            [6.0, 0.0, 0.0],
        ],
    );
}

/// A colour map after a declared pattern pigment replaces the pattern's
/// map, as woods.inc's textures use theirs; after a pigment drawn as one
/// colour (turbulence), that colour is the new map's mean.
#[test]
fn a_colour_map_after_a_declared_pattern_replaces_its_map() {
    let scene = load(&format!(
        "{VIEW}#declare P = pigment {{ gradient x }}\n\
         #declare Q = pigment {{ wood turbulence 0.1 }}\n\
         sphere {{ 0, 1 pigment {{ P color_map {{ [0 rgb <1, 0, 0>] [1 rgb <0, 0, 1>] }} }} }}\n\
         sphere {{ <3, 0, 0>, 1 pigment {{ Q color_map {{ [0 rgb <1, 1, 0>] [1 rgb <0, 1, 1>] }} }} }}"
    ))
    .unwrap();
    let material = |i: usize| &scene.materials[scene.shapes[i].material as usize];
    let mapped = material(0).mapped.as_ref().expect("the pattern");
    assert_eq!(mapped.map.len(), 2);
    assert_eq!(mapped.map[1].1.to_array(), [0.0, 0.0, 1.0]);
    assert!(material(1).mapped.is_none());
    assert_eq!(material(1).albedo.to_array(), [0.5, 1.0, 0.5]);
}

/// A surface with no box of its own, clipped and then turned twice (POV-Ray's
/// helix.pov): its box is its clip's box turned, as tight as a box `box`
/// in the same place, not the world box mapped back through each rotation,
/// which widens it every time (helix.pov's were three times too wide). And
/// a bound copied from the clip, which adds no gate, gives every ray the
/// hit the same bound written out, a gate, gives.
#[test]
fn a_turned_clipped_surface_keeps_its_clips_box() {
    let place = "translate -2*z rotate 160*z rotate -90*x rotate <-30, 0, 30>";
    let helix = |bound: &str| {
        format!(
            "{VIEW}quartic {{ <0, 0, 0, 0, 0, 0, 0, 0, 0, 0,  0, 0, 0, 0, 0, 0, -0.1666, 0, 1, 0,\n\
             0, 0, 0, 0, 0, 0, 0, 0.5, 0, -1,  0, 0, 0, 0, 0>\n\
             clipped_by {{ quadric {{ <1, 1, 0>, <0, 0, 0>, <0, 0, 0>, -4 }}\n\
             plane {{ z, 1.4142 }} plane {{ -z, 0 }} }}\n\
             {bound} {place} }}\n"
        )
    };
    let copied = load(&helix("bounded_by { clipped_by }")).unwrap();
    let written = load(&helix(
        "bounded_by { quadric { <1, 1, 0>, <0, 0, 0>, <0, 0, 0>, -4 } }",
    ))
    .unwrap();
    let solid = load(&format!(
        "{VIEW}box {{ <-2, -2, 0>, <2, 2, 1.4142> {place} }}"
    ))
    .unwrap();
    let want = solid.shapes[0].bounds();
    let size = (want.max - want.min).max_element();
    for scene in [&copied, &written] {
        let got = scene.shapes[0].bounds();
        assert!(
            (got.min - want.min).min_element() > -1e-3 * size
                && (want.max - got.max).min_element() > -1e-3 * size,
            "{got:?} against the box's {want:?}"
        );
    }
    // A fan of rays from the camera over the box, and from inside it.
    let centre = ((want.min + want.max) * 0.5).as_dvec3();
    let mut hits = 0;
    for i in 0..4_000 {
        let k = f64::from(i);
        let aim = centre + DVec3::new((k * 0.37).sin(), (k * 0.61).cos(), (k * 0.83).sin()) * 3.0;
        let o = if i % 4 == 0 {
            centre
        } else {
            DVec3::new(0.0, 0.0, -5.0)
        };
        let (a, b) = (
            first_hit(&copied, o, aim - o),
            first_hit(&written, o, aim - o),
        );
        assert_eq!(a, b, "ray {i}");
        hits += usize::from(a.is_some());
    }
    assert!(hits > 400, "{hits} hits");
}

/// A declared object's name alone stands for the object, at the top, in
/// CSG and in a bound, with the modifiers that follow it, as in POV-Ray
/// (which renders `union { Thing }`, warning that `object` is wanted).
/// Any other word where an object must stand is an error at its place.
#[test]
fn a_declared_objects_name_alone_is_the_object() {
    let scene = load(&format!(
        "{VIEW}#declare Ball = sphere {{ 0, 1 }}\n\
         Ball\n\
         union {{ Ball sphere {{ <0, 3, 0>, 1 }} translate 3*x }}\n\
         sphere {{ <0, -3, 0>, 1 bounded_by {{ Ball scale 9 }} }}\n"
    ))
    .unwrap();
    let centres: Vec<[f32; 3]> = scene
        .shapes
        .iter()
        .map(|s| {
            let b = s.bounds();
            ((b.min + b.max) * 0.5).to_array().map(|c| c.round())
        })
        .collect();
    assert_eq!(
        centres,
        [
            [0.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
            [3.0, 3.0, 0.0],
            [0.0, -3.0, 0.0]
        ]
    );
    // A bound left open takes the next words as objects (or transforms of
    // its objects): they are not.
    let err = load(&format!(
        "{VIEW}sphere {{ 0, 1\n  bounded_by {{ sphere {{ 0, 2 }}\n  pigment {{ rgb 1 }} }}\n"
    ))
    .unwrap_err();
    assert!(err.is_bad_input());
    assert!(
        err.to_string()
            .contains("t.pov:4:3: expected an object, found `pigment`"),
        "{err}"
    );
}

/// `bounded_by` and `clipped_by` blocks as POV-Ray 3.7 reads them
/// (`Parse_Bound_Clip`): transforms after a block's objects move them all,
/// and a second block adds its objects to the first's. Linking the two
/// lists where one already has objects is an error, as in POV-Ray.
#[test]
fn bound_and_clip_blocks_add_up_and_take_transforms() {
    let along_z = |scene: &Scene, x: f64, y: f64| {
        first_hit(scene, DVec3::new(x, y, -5.0), DVec3::Z).is_some()
    };
    // Kept where y < 0 and x < 0: the first block's plane turned a
    // quarter to face -x, then y < 0 from the second block.
    let clipped = load(&format!(
        "{VIEW}sphere {{ 0, 1 clipped_by {{ plane {{ y, 0 }} rotate 90*z }}\n\
         clipped_by {{ plane {{ y, 0 }} }} }}"
    ))
    .unwrap();
    let seen: Vec<bool> = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
        .iter()
        .map(|&(x, y)| along_z(&clipped, x, y))
        .collect();
    assert_eq!(
        seen,
        [false, true, false, false],
        "rotate 90*z turns y to -x"
    );
    // Two bounds of a CSG object: a ray must meet both. The first, moved
    // by its block, covers x > 0.2; the second y < 0.2.
    let bounded = load(&format!(
        "{VIEW}intersection {{ sphere {{ 0, 1 }} sphere {{ 0, 1.2 }}\n\
         bounded_by {{ box {{ <-1, -2, -2>, <1, 2, 2> }} translate 1.2*x }}\n\
         bounded_by {{ box {{ <-2, -2, -2>, <2, 0.2, 2> }} }} }}"
    ))
    .unwrap();
    let seen: Vec<bool> = [(0.5, -0.5), (0.5, 0.5), (-0.5, -0.5), (0.0, 0.0)]
        .iter()
        .map(|&(x, y)| along_z(&bounded, x, y))
        .collect();
    assert_eq!(seen, [true, false, false, false]);
    // Linked lists cannot grow, and a list with objects cannot be linked.
    for (mods, message) in [
        (
            "clipped_by { plane { y, 0 } } bounded_by { clipped_by } bounded_by { box { -1, 1 } }",
            "`bounded_by` objects after `bounded_by { clipped_by }`",
        ),
        (
            "bounded_by { box { -2, 2 } } clipped_by { plane { y, 0 } } bounded_by { clipped_by }",
            "`bounded_by { clipped_by }` after `bounded_by` objects",
        ),
    ] {
        let err = load(&format!("{VIEW}sphere {{ 0, 1 {mods} }}")).unwrap_err();
        assert!(
            err.is_bad_input() && err.to_string().contains(message),
            "{err}"
        );
    }
}

/// POV-Ray culls an object by the box its removed `bounded_by` leaves only
/// with three objects or more in the scene, lights counted and a union
/// without bounds or clips counted by its children (Debian's
/// `Bounding_Threshold = 3`); a bound no ray can pass leaves nothing.
#[test]
fn a_removed_bounds_box_culls_from_three_objects_on() {
    let bounded = "sphere { 0, 1.5 bounded_by { box { <-2, -2, -2>, <-0.5, 2, 2> } } }";
    let light = "light_source { <5, 5, -5> color rgb 1 }";
    // A ray at x = 0.5: outside the bound's box, inside the sphere.
    let seen = |text: &str| {
        let scene = load(&format!("{VIEW}{text}")).unwrap();
        first_hit(&scene, DVec3::new(0.5, 0.0, -5.0), DVec3::Z).is_some()
    };
    assert!(seen(&format!("{bounded}\n{light}")), "two objects: no cull");
    assert!(
        !seen(&format!("{bounded}\n{light}\n{light}")),
        "three: culled"
    );
    assert!(
        !seen(&format!(
            "{bounded}\nunion {{ sphere {{ 5*x, 1 }} {light} }}"
        )),
        "a union's children count one by one"
    );
    assert!(
        seen(&format!(
            "{bounded}\nunion {{ sphere {{ 5*x, 1 }} {light} bounded_by {{ box {{ -9, 9 }} }} }}"
        )),
        "a bounded union counts as one"
    );
    // Bounds whose boxes are apart: no object at all, from three on.
    let apart = "sphere { 0, 1.5 bounded_by { box { <-2, -2, -2>, <-0.5, 2, 2> } \
                 box { <0.5, -2, -2>, <2, 2, 2> } } }";
    let scene = load(&format!("{VIEW}{apart}\n{light}\n{light}")).unwrap();
    assert!(scene.shapes.is_empty());
    assert!(scene.warnings.iter().any(|w| w.contains("no ray can pass")));
}

/// A loop that wraps an object in itself on every pass, and never ends,
/// stops at the nesting limit with an error at the object (it overflowed
/// the stack), and one that doubles an object on every pass stops when the
/// copies pass their limit (it filled the memory).
#[test]
fn objects_grown_by_a_loop_stop_at_their_limits() {
    let err = load(&format!(
        "{VIEW}#declare U = sphere {{ 0, 1 }}\n\
         #while (1)\n  #declare U = union {{ object {{ U }} sphere {{ x, 1 }} }}\n#end\n"
    ))
    .unwrap_err();
    assert!(err.is_bad_input());
    assert!(
        err.to_string()
            .contains("t.pov:4:16: objects nest deeper than 256"),
        "{err}"
    );
    let err = load(&format!(
        "{VIEW}#declare U = sphere {{ 0, 1 }}\n\
         #while (1)\n  #declare U = union {{ U U }}\n#end\n"
    ))
    .unwrap_err();
    assert!(err.is_bad_input());
    assert!(
        err.to_string()
            .contains("declared objects have been copied 2097152 objects"),
        "{err}"
    );
}

/// A loop whose body ends in a declaration with no `;` (an object's) runs
/// each pass after the last, not inside it: 5,000 passes read, where each
/// pass had nested one level deeper.
#[test]
fn a_loop_ending_in_a_declared_object_runs_pass_after_pass() {
    let scene = load(&format!(
        "{VIEW}#declare I = 0;\n\
         #while (I < 5000)\n  #declare I = I + 1;\n  #declare S = sphere {{ <I, 0, 0>, 1 }}\n#end\n\
         object {{ S }}\n"
    ))
    .unwrap();
    let b = scene.shapes[0].bounds();
    assert!((b.min.x - 4999.0).abs() < 1e-2, "{b:?}");
}

#[test]
fn a_surface_its_context_leaves_nothing_of_is_left_out() {
    // From a fuzz of random trees against POV-Ray, which draws nothing
    // here: the ellipsoid lies where the clip and its sibling leave nothing
    // of it, so cutting it to them left an empty box, which stopped the read.
    let scene = load(&format!(
        "{VIEW}intersection {{ intersection {{\n\
         intersection {{ union {{ sphere {{ <0.483, 0.113, 0.451>, 1.035 rotate <-7.4, 78.4, 34.3> rotate <-8.5, -57.7, -24.2> }} }}\n\
         intersection {{ torus {{ 0.513, 0.192 scale 0.622 }} }} }}\n\
         merge {{ merge {{ }}\n\
         intersection {{ quadric {{ <1.991, 2.043, 2.228>, <0, 0, 0>, <0, 0, 0>, -1 scale 1.148 translate <-0.683, 0.247, -0.549> }}\n\
         translate <-0.518, 0.393, 0.157> scale 1.317 }}\n\
         clipped_by {{ quadric {{ <1.192, 0.584, 0.932>, <0, 0, 0>, <0, 0, 0>, -1 }} }} rotate <15.6, 10.3, -3.1> rotate <62.7, -28.7, 49.9> }}\n\
         }} box {{ -2.2, 2.2 }} }}\n"
    ))
    .unwrap();
    assert!(scene.shapes.is_empty());
}

#[test]
fn an_object_whose_parts_do_not_overlap_is_left_out_with_a_warning() {
    // From the same fuzz (POV-Ray draws the sphere alone): the reader's
    // boxes of the parts overlap, the tree's own, tighter, do not. The
    // tree holds nothing, which stopped the read.
    let scene = load(&format!(
        "{VIEW}intersection {{ intersection {{ union {{ difference {{ }} union {{ quartic {{ <1, 0, 0, 0, 2, 0, 0, 2, 0, -1.494804, \
         0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 2, 0, 0.855458, 0, 0, 0, 0, 1, 0, -1.494804, 0, 0.182952> \
         rotate <-31.5, -36.8, -88.2> }} }} }}\n\
         intersection {{ difference {{ box {{ <-0.883, -1.281, 0.298>, <0.591, -0.156, 0.767> inverse }} }}\n\
         intersection {{ cone {{ <1.169, -0.983, -0.495>, 0.504, <0.665, -0.486, -0.213>, 0 scale 1.227 scale <1.532, 0.529, 0.745> }} }}\n\
         scale 0.835 translate <0.512, 0.321, 0.226> }}\n\
         clipped_by {{ cylinder {{ <-0.023, -0.814, -1.165>, <-0.556, 0.941, 0.678>, 0.843 scale 0.602 }} }} \
         translate <0.305, 0.081, 0.768> rotate <60.9, 89.6, -55.3> }}\n\
         box {{ -2.2, 2.2 }} }}\n\
         sphere {{ 0, 0.5 }}\n"
    ))
    .unwrap();
    assert_eq!(scene.shapes.len(), 1);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("t.pov:2:1: this object is empty")),
        "{:?}",
        scene.warnings
    );
}

/// POV-Ray removes a whole quadric's `bounded_by` only where it boxes the
/// quadric itself (`Quadric::Compute_BBox`): the axis-aligned forms, once
/// linear terms are moved into a shift, and nothing with mixed terms.
#[test]
fn quadrics_povray_boxes_itself() {
    use glam::DMat3;

    use super::build::quadric_boxed;
    let diag = |x: f64, y: f64, z: f64| DMat3::from_diagonal(DVec3::new(x, y, z));
    // Ellipsoid, moved off the origin by linear terms.
    assert!(quadric_boxed(
        diag(1.0, 2.0, 3.0),
        DVec3::new(0.4, 0.0, -1.0),
        -1.0
    ));
    // Cylinder along y, cone along z, one-sheet hyperboloid along y.
    assert!(quadric_boxed(diag(1.0, 0.0, 1.0), DVec3::ZERO, -1.0));
    assert!(quadric_boxed(diag(1.0, 1.0, -1.0), DVec3::ZERO, 0.0));
    assert!(quadric_boxed(diag(1.0, -1.0, 1.0), DVec3::ZERO, -0.3));
    // Paraboloid along y: x² + z² − y, written with A < 0 too.
    assert!(quadric_boxed(
        diag(1.0, 0.0, 1.0),
        DVec3::new(0.0, -1.0, 0.0),
        0.0
    ));
    assert!(quadric_boxed(
        diag(-1.0, 0.0, -1.0),
        DVec3::new(0.0, 1.0, 0.0),
        0.0
    ));
    // A saddle, a plane, a sphere's empty inside and any mixed term: no box.
    assert!(!quadric_boxed(
        diag(1.0, -1.0, 0.0),
        DVec3::new(0.0, 0.0, -1.0),
        0.0
    ));
    assert!(!quadric_boxed(
        diag(0.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        0.0
    ));
    assert!(!quadric_boxed(diag(1.0, 1.0, 1.0), DVec3::ZERO, 1.0));
    let mut mixed = diag(1.0, 1.0, 1.0);
    mixed.x_axis.y = 0.25;
    mixed.y_axis.x = 0.25;
    assert!(!quadric_boxed(mixed, DVec3::ZERO, -1.0));
}
