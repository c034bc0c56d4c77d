//! SVG import: tags from each source, unit selection, geometry in canvas coordinates, and
//! errors that say where the file is wrong.

use gmotion::scene::{Node, Scene};
use gmotion_import_svg::{ImportError, ImportOptions, Imported, TagFrom, Units, load, parse};
use kurbo::{Affine, Point, Rect, Shape as _};

fn import(body: &str, opts: ImportOptions) -> Imported {
    let text = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="200" height="200">{body}</svg>"#
    );
    parse(&text, "test.svg", &opts).unwrap_or_else(|e| panic!("{e}"))
}

fn tags(scene: &Scene) -> Vec<(String, usize)> {
    scene.shapes.iter().map(|s| (s.tag.clone(), s.id)).collect()
}

fn with(tag_from: TagFrom, units: Units) -> ImportOptions {
    ImportOptions {
        tag_from,
        units,
        ..ImportOptions::default()
    }
}

fn close(a: Point, b: Point) -> bool {
    a.distance(b) < 1e-3
}

const SOURCES: &str = r#"
    <g id="Wheels_3_" class="car">
        <rect data-tag="bolt" class="x" width="10" height="10"/>
        <rect width="10" height="10"/>
    </g>
    <g id="Trees_2_">
        <circle inkscape:label="oak" r="5"/>
        <circle class="pine  tall" r="5"/>
        <circle r="5"/>
    </g>
    <path d="M0 0 L5 5 Z" stroke="black"/>
"#;

#[test]
fn tags_come_from_the_nearest_source() {
    let scene = import(SOURCES, with(TagFrom::Auto, Units::Paths)).scene;
    let want = [
        ("bolt", 0),
        ("car", 0),
        ("oak", 0),
        ("pine", 0),
        ("Trees", 0),
        ("path", 0),
    ];
    assert_eq!(tags(&scene), want.map(|(t, i)| (t.to_string(), i)));
    // With group units the tagged `car` group is one shape; the untagged layer is not.
    let auto = import(SOURCES, ImportOptions::default()).scene;
    let want = [
        ("car", 0),
        ("oak", 0),
        ("pine", 0),
        ("Trees", 0),
        ("path", 0),
    ];
    assert_eq!(tags(&auto), want.map(|(t, i)| (t.to_string(), i)));
}

#[test]
fn a_single_source_ignores_the_others() {
    for (from, want) in [
        (
            TagFrom::DataTag,
            ["bolt", "rect", "circle", "circle", "circle", "path"],
        ),
        (
            TagFrom::Class,
            ["x", "car", "circle", "pine", "circle", "path"],
        ),
        (
            TagFrom::Label,
            ["rect", "rect", "oak", "circle", "circle", "path"],
        ),
        (
            TagFrom::Layer,
            ["Wheels", "Wheels", "Trees", "Trees", "Trees", "path"],
        ),
    ] {
        let got: Vec<String> = tags(&import(SOURCES, with(from, Units::Paths)).scene)
            .into_iter()
            .map(|(t, _)| t)
            .collect();
        assert_eq!(got, want, "{from:?}");
    }
}

#[test]
fn use_instances_take_the_referenced_element_tag() {
    let body = r##"
        <defs><path id="leaf" class="leaf" d="M0 0 L10 0 L10 10 Z"/>
              <g id="pair"><rect class="a" width="5" height="5"/><rect class="b" x="5" width="5" height="5"/></g></defs>
        <use href="#leaf" x="20"/><use href="#leaf" x="40"/>
        <use href="#pair" y="50"/>
    "##;
    let scene = import(body, ImportOptions::default()).scene;
    let got = tags(&scene);
    let want = [("leaf", 0), ("leaf", 1), ("a", 0), ("b", 0)].map(|(t, i)| (t.to_string(), i));
    assert_eq!(got, want);
    // The instances sit where `x` puts them.
    assert!(
        close(scene.shapes[1].bbox.origin(), Point::new(40.0, 0.0)),
        "{:?}",
        scene.shapes[1].bbox
    );
}

#[test]
fn a_tagged_group_is_one_unit() {
    let body = r#"
        <g class="hero" transform="translate(100 0)">
            <rect width="10" height="10"/><circle cx="20" r="5"/>
            <g class="hat"><rect y="-10" width="10" height="5"/></g>
        </g>
        <rect class="x" width="1" height="1"/><rect class="y" width="1" height="1"/><rect class="x" width="1" height="1"/>
    "#;
    let auto = import(body, ImportOptions::default()).scene;
    assert_eq!(
        tags(&auto),
        [("hero", 0), ("x", 0), ("y", 0), ("x", 1)].map(|(t, i)| (t.to_string(), i))
    );
    let hero = &auto.shapes[0];
    let node = auto.unit_node(0).expect("unit node");
    assert!(matches!(node, Node::Group(g) if g.unit == Some(0) && g.children.len() == 3));
    assert_eq!(hero.bbox, Rect::new(100.0, -10.0, 125.0, 10.0));
    for (i, s) in auto.shapes.iter().enumerate() {
        assert_eq!(auto.unit_node(i).and_then(Node::unit), Some(i), "{}", s.tag);
        assert_eq!(s.z, i);
    }

    let paths = import(body, with(TagFrom::Auto, Units::Paths)).scene;
    assert_eq!(paths.shapes.len(), 6);
    assert_eq!(
        tags(&paths)[..3],
        [("hero", 0), ("hero", 1), ("hat", 0)].map(|(t, i)| (t.to_string(), i))
    );
}

#[test]
fn groups_mode_takes_outermost_layers() {
    let body = r#"
        <g id="Layer_1"><rect width="1" height="1"/><g id="Sub_1"><rect width="2" height="2"/></g></g>
        <g><rect class="loose" width="3" height="3"/></g>
    "#;
    let scene = import(body, with(TagFrom::Auto, Units::Groups)).scene;
    assert_eq!(
        tags(&scene),
        [("Layer_1", 0), ("loose", 0)].map(|(t, i)| (t.to_string(), i))
    );
    // Auto units do not treat a bare layer id as a tag that groups.
    let auto = import(body, ImportOptions::default()).scene;
    assert_eq!(auto.shapes.len(), 3);
}

#[test]
fn centroids_are_area_centroids_in_canvas_space() {
    let body = r#"
        <rect x="10" y="20" width="40" height="20"/>
        <g transform="translate(100 100) scale(2)"><circle cx="5" cy="-5" r="10"/></g>
        <path d="M0 0 H30 V10 H10 V30 H0 Z"/>
        <line x1="0" y1="0" x2="10" y2="4" stroke="black"/>
    "#;
    let scene = import(body, ImportOptions::default()).scene;
    let c: Vec<Point> = scene.shapes.iter().map(|s| s.centroid).collect();
    assert!(close(c[0], Point::new(30.0, 30.0)), "{:?}", c[0]);
    assert!(close(c[1], Point::new(110.0, 90.0)), "{:?}", c[1]);
    // An L: 300 at (15, 5) plus 200 at (5, 20) → (11, 11); its box centre would be (15, 15).
    assert!(close(c[2], Point::new(11.0, 11.0)), "{:?}", c[2]);
    // A stroke alone has no area: the box centre stands in.
    assert!(close(c[3], Point::new(5.0, 2.0)), "{:?}", c[3]);
    assert_eq!(scene.shapes[1].bbox, Rect::new(90.0, 70.0, 130.0, 110.0));
}

#[test]
fn view_box_and_nested_transforms_map_to_the_canvas() {
    let text = r#"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="200" viewBox="0 0 100 50">
        <g transform="translate(10 5)"><g transform="rotate(90)"><rect width="10" height="4"/></g></g></svg>"#;
    let scene = parse(text, "vb.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    assert_eq!((scene.width, scene.height), (400.0, 200.0));
    let shape = &scene.shapes[0];
    // rotate(90) takes the rect to x∈[-4,0], y∈[0,10]; then +(10,5); then ×4.
    let want = Rect::new(24.0, 20.0, 40.0, 60.0);
    let got = shape.bbox;
    assert!(
        (got.x0 - want.x0).abs() < 1e-4 && (got.y1 - want.y1).abs() < 1e-4,
        "{got:?}"
    );
    // parent_transform places the node's own geometry on the canvas.
    let Some(Node::Path(p)) = scene.unit_node(0) else {
        panic!("path unit")
    };
    let placed = (shape.parent_transform * p.path.clone()).bounding_box();
    assert!(
        (placed.x0 - want.x0).abs() < 1e-4 && (placed.y0 - want.y0).abs() < 1e-4,
        "{placed:?}"
    );
    assert!(close(
        shape.parent_transform * Point::ORIGIN,
        Point::new(40.0, 20.0)
    ));
    assert_eq!(scene.root.transform, Affine::scale(4.0));
}

#[test]
fn synthetic_ids_never_reach_the_scene() {
    let body = r#"<rect id="real" width="1" height="1"/><rect width="1" height="1"/><rect id="real" width="1" height="1"/>"#;
    let scene = import(body, ImportOptions::default()).scene;
    let ids: Vec<&str> = scene.root.children.iter().map(Node::id).collect();
    assert_eq!(ids, ["real", "", ""]);
}

#[test]
fn unsupported_features_are_named_in_warnings() {
    let body = r#"<filter id="f"><feMorphology radius="2"/></filter>
        <g id="shadow" filter="url(#f)"><rect width="5" height="5"/></g>
        <rect width="5" height="5" style="mix-blend-mode:multiply"/>"#;
    let imported = import(body, ImportOptions::default());
    let w = imported
        .warnings
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n");
    assert!(
        w.contains("test.svg: <g id=\"shadow\"> (line 2): filter drawn as an image"),
        "{w}"
    );
    assert!(w.contains("mix-blend-mode multiply ignored"), "{w}");
    assert_eq!(imported.scene.shapes.len(), 2);
}

#[test]
fn malformed_xml_reports_line_and_column() {
    let text = "<svg xmlns=\"http://www.w3.org/2000/svg\">\n  <rect width=\"1\">\n</svg>";
    let err = parse(text, "bad.svg", &ImportOptions::default()).unwrap_err();
    match &err {
        ImportError::Xml { line, column, .. } => assert_eq!((*line, *column), (3, 1)),
        other => panic!("{other}"),
    }
    let msg = err.to_string();
    assert_eq!(
        msg,
        "bad.svg:3:1: malformed XML: expected 'rect' tag, not 'svg'"
    );
}

#[test]
fn other_errors_say_what_is_wrong() {
    let opts = ImportOptions::default();
    let missing = load(std::path::Path::new("/no/such/file.svg"), &opts).unwrap_err();
    assert!(matches!(missing, ImportError::Read(_)), "{missing}");
    assert!(
        missing
            .to_string()
            .starts_with("/no/such/file.svg: cannot read")
    );

    let empty = parse("", "empty.svg", &opts).unwrap_err();
    assert!(
        matches!(
            empty,
            ImportError::Xml {
                line: 1,
                column: 1,
                ..
            }
        ),
        "{empty}"
    );

    let html = parse("<html/>", "page.html", &opts).unwrap_err();
    assert!(
        matches!(&html, ImportError::NotSvg { found, .. } if found == "html"),
        "{html}"
    );

    let zero = parse(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="0" height="10"/>"#,
        "z.svg",
        &opts,
    )
    .unwrap_err();
    assert!(matches!(zero, ImportError::Size { .. }), "{zero}");
}

#[test]
fn an_empty_drawing_imports_with_no_shapes() {
    let imported = import(
        r#"<rect width="10" height="10" fill="none"/>"#,
        ImportOptions::default(),
    );
    assert!(imported.scene.shapes.is_empty());
}

#[test]
fn inkscape_layers_name_but_do_not_group() {
    let body = r#"
        <g inkscape:groupmode="layer" inkscape:label="Layer 1" id="layer1">
            <rect width="1" height="1"/>
            <g inkscape:label="bird"><rect width="2" height="2"/><rect x="3" width="2" height="2"/></g>
        </g>"#;
    let auto = import(body, ImportOptions::default()).scene;
    let want = [("Layer 1", 0), ("bird", 0)].map(|(t, i)| (t.to_string(), i));
    assert_eq!(tags(&auto), want);
    let groups = import(body, with(TagFrom::Auto, Units::Groups)).scene;
    assert_eq!(tags(&groups), [("Layer 1".to_string(), 0)]);
}

#[test]
fn a_named_group_without_id_or_transform_is_kept() {
    // Inkscape names a group by its label and Illustrator by `data-name`, often with no
    // id and no transform: the group stays in the tree with its name, its shapes in it.
    let body = r#"
        <g inkscape:label="wing"><rect width="2" height="2"/><rect x="3" width="2" height="2"/></g>
        <g data-name="tail feathers"><rect x="6" width="2" height="2"/></g>
        <g><rect x="9" width="2" height="2"/></g>"#;
    for opts in [ImportOptions::default(), with(TagFrom::Auto, Units::Paths)] {
        let scene = import(body, opts).scene;
        let named: Vec<(&str, usize)> = scene
            .root
            .children
            .iter()
            .filter_map(|n| match n {
                Node::Group(g) if !g.label.is_empty() => Some((g.label.as_str(), g.children.len())),
                _ => None,
            })
            .collect();
        assert_eq!(named, [("wing", 2), ("tail feathers", 1)]);
        // The unnamed group is still looked through: its rect is a child of the root.
        assert_eq!(scene.root.children.len(), 3);
    }
}

#[test]
fn a_group_unit_is_tagged_by_what_makes_it_one() {
    let text = r##"<svg xmlns="http://www.w3.org/2000/svg" class="drawing" width="100" height="100">
        <defs><g id="bird" class="bird"><rect width="2" height="2"/><rect x="3" width="2" height="2"/></g></defs>
        <g id="Layer_1"><rect width="1" height="1"/></g>
        <use href="#bird" x="10"/><use href="#bird" x="20"/></svg>"##;
    let groups = parse(text, "t.svg", &with(TagFrom::Auto, Units::Groups))
        .unwrap()
        .scene;
    let want = [("Layer_1", 0), ("bird", 0), ("bird", 1)].map(|(t, i)| (t.to_string(), i));
    assert_eq!(tags(&groups), want);
    let auto = parse(text, "t.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    let want = [("drawing", 0), ("bird", 0), ("bird", 1)].map(|(t, i)| (t.to_string(), i));
    assert_eq!(tags(&auto), want);
    assert!(matches!(auto.unit_node(1), Some(Node::Group(_))));
}

#[test]
fn layer_counters_go_only_where_they_tell_copies_apart() {
    // Illustrator: two layers, and copies of `eye` (`eye_1_`, `eye_2_`); Figma: `Vector`
    // and its copy `Vector_2`.
    let body = r#"
        <g id="Layer_1"><rect width="1" height="1"/></g>
        <g id="Layer_2"><rect x="2" width="1" height="1"/></g>
        <g id="eye_1_"><rect x="4" width="1" height="1"/></g>
        <g id="eye_2_"><rect x="6" width="1" height="1"/></g>
        <g id="Vector"><rect x="8" width="1" height="1"/></g>
        <g id="Vector_2"><rect x="10" width="1" height="1"/></g>
    "#;
    let scene = import(body, with(TagFrom::Layer, Units::Groups)).scene;
    let want = [
        ("Layer_1", 0),
        ("Layer_2", 0),
        ("eye", 0),
        ("eye", 1),
        ("Vector", 0),
        ("Vector", 1),
    ];
    assert_eq!(tags(&scene), want.map(|(t, i)| (t.to_string(), i)));
}

#[test]
fn text_in_a_missing_font_is_drawn_in_the_default_family_and_said_so() {
    let text = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100">
        <style>.st0{font-family:'Montserrat-SemiBold';font-size:20px}</style>
        <text id="title" class="st0" x="10" y="40">Hello</text>
        <text id="plain" x="10" y="80" font-family="sans-serif" font-size="20">World</text>
        <text id="fallback" x="100" y="80" font-family="NoSuchFont, sans-serif" font-size="20">!</text>
    </svg>"#;
    let imported = parse(text, "t.svg", &ImportOptions::default()).unwrap();
    // Nothing vanishes: a generic family maps to an installed font, and a missing one
    // falls back to the default family.
    let units: Vec<&str> = imported
        .scene
        .shapes
        .iter()
        .map(|s| s.tag.as_str())
        .collect();
    assert_eq!(units.len(), 3, "{units:?}");
    let said: Vec<String> = imported.warnings.iter().map(ToString::to_string).collect();
    let missing: Vec<&String> = said
        .iter()
        .filter(|w| w.contains("is not installed"))
        .collect();
    // One warning, naming the element and the font; a list that ends in a generic family
    // falls back as its author asked.
    assert_eq!(missing.len(), 1, "{said:?}");
    assert!(
        missing[0].contains("<text id=\"title\">") && missing[0].contains("`Montserrat-SemiBold`"),
        "{said:?}"
    );
}

/// An element drawn several times (a marker's image at each of a path's five vertices) is
/// warned about once, not once per copy.
#[test]
fn a_warning_about_a_copied_element_is_said_once() {
    let imported = import(
        r#"<marker id="m" markerWidth="10" markerHeight="10"><image id="pic" href="missing.png" width="10" height="10"/></marker>
        <path d="M 10 10 L 50 10 L 90 10 L 130 10 L 170 10" stroke="black" marker-start="url(#m)" marker-mid="url(#m)" marker-end="url(#m)"/>"#,
        ImportOptions::default(),
    );
    let about: Vec<String> = imported
        .warnings
        .iter()
        .map(ToString::to_string)
        .filter(|w| w.contains("missing.png"))
        .collect();
    assert_eq!(about.len(), 1, "{about:#?}");
}

/// Under `--units paths` a text's glyph runs are units of their own; they still answer to
/// the text's id and the ids of the groups around it, as the text does under `auto`
/// (the group's name is their tag).
#[test]
fn a_texts_glyph_runs_keep_the_texts_and_its_groups_names_under_units_paths() {
    let body = r#"<g id="heading"><text id="title" x="10" y="40" font-family="sans-serif" font-size="20">Hi <tspan fill="red">there</tspan></text></g>"#;
    for units in [Units::Auto, Units::Paths] {
        let scene = import(body, with(TagFrom::Auto, units)).scene;
        assert!(!scene.shapes.is_empty(), "{units:?}: no font to draw with");
        for s in &scene.shapes {
            assert_eq!(s.tag, "heading", "{units:?}");
            // The tag is the group's name; its own id is left out of the aliases.
            assert!(
                s.aliases.iter().any(|a| a == "title"),
                "{units:?}: {:?}",
                s.aliases
            );
        }
    }
}

/// A text in a missing sans-serif family (Montserrat, as Illustrator exports name it) is
/// drawn in the sans-serif family, not the serif one usvg falls back to; a missing serif
/// family (Georgia) in the serif one. Judged by the outlines: the same box as the generic
/// family's text.
#[test]
fn a_missing_font_falls_back_to_a_font_of_its_kind() {
    let outline = |family: &str| {
        let body = format!(
            r#"<text id="t" x="10" y="100" font-family="{family}" font-size="40">Hamburg</text>"#
        );
        let imported = import(&body, ImportOptions::default());
        let said: Vec<String> = imported.warnings.iter().map(ToString::to_string).collect();
        (imported.scene.shapes.first().map(|s| s.bbox), said)
    };
    let (sans, _) = outline("sans-serif");
    let (serif, _) = outline("serif");
    if sans.is_none() || sans == serif {
        return; // one font or none on this machine: nothing to tell apart
    }
    for (missing, box_of_kind, kind) in [
        ("Montserrat", sans, "sans"),
        ("Montserrat-SemiBold", sans, "sans"),
        ("Arial Black", sans, "sans"),
        ("Georgia", serif, "serif"),
    ] {
        if gmotion_import_svg::fonts::installed(
            &gmotion_import_svg::fonts::database(&Default::default()),
            missing,
        ) {
            continue;
        }
        let (got, said) = outline(missing);
        assert_eq!(
            got, box_of_kind,
            "{missing} is drawn in the {kind} family: {said:?}"
        );
        let warning = said
            .iter()
            .find(|w| w.contains("is not installed"))
            .unwrap_or_else(|| panic!("{said:?}"));
        let generic = if kind == "sans" {
            usvg::fontdb::Family::SansSerif
        } else {
            usvg::fontdb::Family::Serif
        };
        let db = gmotion_import_svg::fonts::database(&Default::default());
        let named = db.family_name(&generic).to_string();
        assert!(
            warning.contains(&format!("drawn in `{named}`")),
            "{warning}"
        );
    }
}
