//! Structure in, structure out, for After Effects files: a rule that names a parent layer
//! or a null moves its whole rig once, through parenting, as After Effects would. Judged
//! by real players against the source with that parent's position offset by hand.

use std::path::PathBuf;
use std::process::Command;

use serde_json::Value;

use crate::support::files_with_extension;
use crate::support::pictures::{Judge, load};
use crate::support::players::{Player, frame_path, play};
use crate::support::root;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("rigs", name)
}

/// Runs gmotion with `args`; fails the test with its message when it fails.
fn gmotion(args: &[&std::ffi::OsStr]) -> String {
    let out = bin().args(args).output().expect("run gmotion");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "gmotion {args:?}: {err}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The files of the Lottie corpus (fetched by `tests/conformance/install.sh`).
fn corpus_files() -> Vec<PathBuf> {
    files_with_extension(
        &root().join("tests/conformance/lottie-corpus"),
        "json",
        "run `bash tests/conformance/install.sh` to fetch the Lottie corpus",
    )
}

/// The root layers of `doc` that parent other layers and have no parent themselves, the
/// one that moves the most layers first.
fn top_parents(doc: &Value) -> Vec<i64> {
    let layers = doc["layers"].as_array().expect("layers");
    let parent_of = |ind: i64| {
        layers
            .iter()
            .find(|l| l["ind"].as_i64() == Some(ind))
            .and_then(|l| l["parent"].as_i64())
    };
    let top = |mut ind: i64| {
        for _ in 0..layers.len() {
            match parent_of(ind) {
                Some(p) => ind = p,
                None => break,
            }
        }
        ind
    };
    let mut moved: Vec<(i64, usize)> = Vec::new();
    for l in layers {
        if let Some(p) = l["parent"].as_i64() {
            let t = top(p);
            match moved.iter_mut().find(|(i, _)| *i == t) {
                Some(m) => m.1 += 1,
                None => moved.push((t, 1)),
            }
        }
    }
    moved.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    moved.into_iter().map(|(i, _)| i).collect()
}

/// The names the unit or rig on the layer with index `ind` answers to by itself (its tag,
/// then its own aliases, as `check --shapes` lists them), each with the indices of every
/// layer whose unit or rig answers to it by itself (a name two layers share moves both).
fn own_names(listing: &str, ind: i64) -> Vec<(String, Vec<i64>)> {
    // A listed unit's own names: its tag, then what it is `also`; and its layer's index.
    let own = |line: &str| -> (Vec<String>, Option<i64>) {
        let line = line.trim_start().trim_start_matches("rig ");
        let mut names = vec![line.split(':').next().unwrap_or("").to_string()];
        if let Some(rest) = line.split("  also ").nth(1) {
            let list = rest.split("  ").next().unwrap_or("");
            names.extend(list.split(", ").map(str::to_string));
        }
        let ind = line
            .rsplit("(ind ")
            .next()
            .and_then(|r| r.trim_end().strip_suffix(')'))
            .and_then(|n| n.parse().ok());
        (names, ind)
    };
    let units: Vec<(Vec<String>, Option<i64>)> = listing.lines().skip(1).map(own).collect();
    let Some((names, _)) = units.iter().find(|(_, i)| *i == Some(ind)) else {
        return Vec::new();
    };
    names
        .iter()
        .map(|name| {
            let owners = units
                .iter()
                .filter(|(n, _)| n.contains(name))
                .filter_map(|(_, i)| *i)
                .collect();
            (name.clone(), owners)
        })
        .collect()
}

/// Adds `(dx, dy)` to the position of `layer`, whatever its encoding: static or keyed,
/// joined or split into `x` and `y`, with legacy end values (`e`) too, or driven by an
/// expression.
fn offset_position(layer: &mut Value, dx: f64, dy: f64) {
    fn shift(v: &mut Value, d: &[f64]) {
        if let Some(a) = v.as_array_mut() {
            for (x, d) in a.iter_mut().zip(d) {
                if let Some(n) = x.as_f64() {
                    *x = (n + d).into();
                }
            }
        } else if let Some(n) = v.as_f64() {
            *v = (n + d[0]).into();
        }
    }
    fn property(p: &mut Value, d: &[f64]) {
        let keyed = p["a"].as_i64() == Some(1)
            || p["k"]
                .as_array()
                .is_some_and(|k| k.first().is_some_and(Value::is_object));
        if keyed {
            for key in p["k"].as_array_mut().into_iter().flatten() {
                for end in ["s", "e"] {
                    if let Some(v) = key.get_mut(end) {
                        shift(v, d);
                    }
                }
            }
        } else {
            shift(&mut p["k"], d);
        }
    }
    let p = &mut layer["ks"]["p"];
    // An expression that does not read the value it is given replaces it (lottie-web runs
    // it; rlottie reads the value): its result is offset too.
    if let Some(x) = p["x"].as_str().filter(|x| !x.contains("value")) {
        p["x"] = format!(
            "{x}\n$bm_rt = [$bm_rt[0] + ({dx}), $bm_rt[1] + ({dy})].concat($bm_rt.slice(2));"
        )
        .into();
    }
    if p["s"].as_bool() == Some(true) || p["s"].as_i64() == Some(1) {
        property(&mut p["x"], &[dx]);
        property(&mut p["y"], &[dy]);
    } else {
        property(p, &[dx, dy]);
    }
}

/// Every rigged file of the After Effects corpus: moving its top-level parent (a null or a
/// drawn layer) with a rule draws, in lottie-web (svg and canvas) and rlottie, what the
/// source draws with that parent's position offset by hand. Before rigs moved whole, a
/// child answered to its parent's name and moved a second time.
#[test]
fn a_rule_on_a_rigs_parent_moves_the_rig_whole_in_every_player() {
    let files = corpus_files();
    let players = [
        Player::LottieWebSvg,
        Player::LottieWebCanvas,
        Player::Rlottie,
    ];
    let mut judge = Judge::new(0.002);
    let mut tried = Vec::new();
    let dir = out_dir("parents");
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let Ok(doc) = serde_json::from_str::<Value>(&text) else {
            continue;
        };
        let parents = top_parents(&doc);
        if parents.is_empty() {
            continue;
        }
        let name = file.file_stem().unwrap().to_string_lossy().into_owned();
        let listing = gmotion(&["check".as_ref(), "--shapes".as_ref(), file.as_os_str()]);
        let layers = doc["layers"].as_array().unwrap();
        let top_level = |ind: &i64| {
            layers
                .iter()
                .any(|l| l["ind"].as_i64() == Some(*ind) && l["parent"].is_null())
        };
        // The parent's tag, unless another layer that answers to it has a parent.
        let Some((tag, owners)) = parents
            .iter()
            .flat_map(|&i| own_names(&listing, i))
            .find(|(_, owners)| owners.iter().all(top_level))
        else {
            panic!("{name}: no top-level parent has a tag only top-level layers share:\n{listing}");
        };
        let w = doc["w"].as_f64().unwrap();
        let (dx, dy) = ((0.07 * w).round(), (-0.05 * w).round());
        // The motion happens in the first half millisecond, then holds: the whole
        // animation is the source offset by (dx, dy).
        let grammar = format!(
            "loop false\n\
             timesplit(0.0001, 0.9999) : [all, {tag}] -> [go, stay]\n\
             animate(affine, world, 0, translate({dx}, {dy})) : [go, {tag}] -> [moved]\n"
        );
        let g = dir.join(format!("{name}.gm"));
        std::fs::write(&g, grammar).unwrap();
        let out = dir.join(format!("{name}.out.json"));
        gmotion(&[
            "animate".as_ref(),
            file.as_os_str(),
            g.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        let mut want = doc.clone();
        for layer in want["layers"].as_array_mut().unwrap() {
            if layer["ind"].as_i64().is_some_and(|i| owners.contains(&i)) {
                offset_position(layer, dx, dy);
            }
        }
        let (ip, op) = (doc["ip"].as_f64().unwrap(), doc["op"].as_f64().unwrap());
        let frames: Vec<f64> = [0.15, 0.4, 0.65, 0.9]
            .iter()
            .map(|f| (f * (op - ip)).floor().max(1.0))
            .collect();
        let width = 160;
        let got = play(
            &format!("rigs-{name}"),
            &std::fs::read_to_string(&out).unwrap(),
            &frames,
            width,
            &players,
        );
        let wanted = play(
            &format!("rigs-{name}-by-hand"),
            &serde_json::to_string(&want).unwrap(),
            &frames,
            width,
            &players,
        );
        for p in players {
            for &f in &frames {
                judge.close(
                    &format!("{name} ({tag} moved) {p:?} frame {f}"),
                    &load(&frame_path(&wanted, p, f)),
                    &load(&frame_path(&got, p, f)),
                );
            }
        }
        tried.push(name);
    }
    // The corpus has 25 rigged files; a fetch that lost some would test less unnoticed.
    assert!(tried.len() >= 25, "rigged files tried: {tried:?}");
    judge.assert_all_close(&dir);
}

/// A layer as (index, name, type, parent).
type Row = (Option<i64>, String, Option<i64>, Option<i64>);

/// The layers of `doc`, in order.
fn layer_tree(doc: &Value) -> Vec<Row> {
    doc["layers"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|l| {
            (
                l["ind"].as_i64(),
                l["nm"].as_str().unwrap_or("").to_string(),
                l["ty"].as_i64(),
                l["parent"].as_i64(),
            )
        })
        .collect()
}

/// Every rigged file of the After Effects corpus keeps its layer tree through `convert`
/// (the same document) and `animate` with motion on every unit: every layer is there in
/// its place with its name, type and index, and its parent is the one it had, reached
/// through the null layers gmotion adds (which only ever sit between a layer and its
/// parent).
#[test]
fn a_rigged_files_layer_tree_survives_convert_and_animate() {
    let files = corpus_files();
    let dir = out_dir("trees");
    let g = dir.join("turn.gm");
    std::fs::write(
        &g,
        "animate(affine, local, 0, rotate(30)) : [all, all] -> [turned]\n",
    )
    .unwrap();
    let mut failures = Vec::new();
    let mut tried = 0;
    for file in &files {
        let Ok(doc) = serde_json::from_str::<Value>(&std::fs::read_to_string(file).unwrap()) else {
            continue;
        };
        if top_parents(&doc).is_empty() {
            continue;
        }
        tried += 1;
        let name = file.file_stem().unwrap().to_string_lossy().into_owned();
        let before = layer_tree(&doc);
        for (what, args) in [
            ("convert", vec!["convert".as_ref(), file.as_os_str()]),
            (
                "animate",
                vec!["animate".as_ref(), file.as_os_str(), g.as_os_str()],
            ),
        ] {
            let out = dir.join(format!("{name}.{what}.json"));
            let mut args = args;
            args.extend(["-o".as_ref(), out.as_os_str()]);
            gmotion(&args);
            let after: Value =
                serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
            let after = layer_tree(&after);
            let original: Vec<Option<i64>> = before.iter().map(|l| l.0).collect();
            // Up the chain from `parent` past the layers gmotion added.
            let parent_of = |mut p: Option<i64>| {
                for _ in 0..after.len() {
                    let Some(added) = after
                        .iter()
                        .skip(before.len())
                        .find(|l| l.0.is_some() && l.0 == p && !original.contains(&l.0))
                    else {
                        break;
                    };
                    p = added.3;
                }
                p
            };
            if after.len() < before.len() {
                failures.push(format!(
                    "{name} {what}: {} layers, was {}",
                    after.len(),
                    before.len()
                ));
                continue;
            }
            for (a, b) in after.iter().zip(&before) {
                let kept = (a.0, &a.1, a.2) == (b.0, &b.1, b.2) && parent_of(a.3) == b.3;
                if !kept {
                    failures.push(format!("{name} {what}: layer {b:?} became {a:?}"));
                }
            }
            for added in &after[before.len()..] {
                if !(added.1.starts_with("gmotion ") && added.2 == Some(3)) {
                    failures.push(format!(
                        "{name} {what}: an added layer is not a gmotion null: {added:?}"
                    ));
                }
            }
        }
    }
    assert!(tried >= 25, "rigged files tried: {tried}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
