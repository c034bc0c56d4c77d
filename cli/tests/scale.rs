//! A million shapes (issue 46): a scene of 999 000 shapes, one `<rect>` a line as a
//! designer's export writes them, is accepted with the default limits. Its XML has about
//! two million nodes (each element and the line break after it), which the old default
//! `xml-nodes` limit of one million refused; usvg's own element limit (a million) lets it
//! through. The scene is imported and its units listed (`check --shapes`), the cheapest
//! command that reads the whole scene; it takes about 30 s on two shared cores.

use std::fmt::Write as _;
use std::process::Command;

/// `n` squares in a grid 1000 wide, one a line.
fn squares(n: usize) -> String {
    let mut svg = String::with_capacity(80 * n + 200);
    svg.push_str(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"4000\" height=\"4000\" viewBox=\"0 0 4000 4000\">\n",
    );
    for i in 0..n {
        let (x, y) = ((i % 1000) * 4, (i / 1000) * 4);
        let _ = writeln!(
            svg,
            "<rect data-tag=\"s\" x=\"{x}\" y=\"{y}\" width=\"3\" height=\"3\" fill=\"#e4572e\"/>"
        );
    }
    svg.push_str("</svg>\n");
    svg
}

#[test]
fn a_scene_of_999_000_shapes_is_accepted_with_the_default_limits() {
    let dir = crate::support::case_dir("scale", "999k");
    let scene = dir.join("squares.svg");
    std::fs::write(&scene, squares(999_000)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .args(["check", "--shapes"])
        .arg(&scene)
        .output()
        .unwrap();
    // 75 MB of scene: not kept.
    let _ = std::fs::remove_file(&scene);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "refused:\n{err}");
    let listed = String::from_utf8_lossy(&out.stdout);
    let first = listed.lines().next().unwrap_or_default();
    assert!(first.ends_with(": 999000 units (4000 × 4000)"), "{first}");
    assert!(listed.contains("\n  s:998999  box [3996.0, 3992.0, 3999.0, 3995.0]"));
}
