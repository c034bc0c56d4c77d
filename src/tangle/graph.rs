//! Grammar graphs (gTangle sec. 5): one node per spatial rule, an edge from rule i to rule j
//! when one of i's output tags is the tag j matches. Their size and depth measure how
//! complex a grammar is (the paper's Table 1), and drawing them shows how it unfolds.
//!
//! Depth is the number of rules on the longest chain of rules that can feed each other,
//! with every cycle (a rule set that rewrites its own output) counted as one level.

use std::fmt::Write;

use crate::grammar::ast::{Expr, ExprKind, Rule};

/// Size and depth of a grammar graph.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GraphStats {
    /// Rules (spatial rules only).
    pub nodes: usize,
    /// Feeding relations between rules.
    pub edges: usize,
    /// Levels on the longest feeding chain (cycles count once).
    pub depth: usize,
}

/// A grammar graph: the spatial rules, the edges between them (with the tags that make
/// them) and each rule's level.
#[derive(Clone, Debug)]
pub struct Graph<'r> {
    /// The spatial rules, in grammar order.
    pub rules: Vec<&'r Rule>,
    /// `(from, to, tag)`: rule `from` outputs `tag`, which rule `to` matches.
    pub edges: Vec<(usize, usize, String)>,
    /// Each rule's level: 0 for rules fed by nothing, else one more than its deepest feeder
    /// outside its own cycle.
    pub levels: Vec<usize>,
}

impl<'r> Graph<'r> {
    /// The graph of the spatial rules among `rules`.
    pub fn new(rules: &[&'r Rule]) -> Graph<'r> {
        let rules: Vec<&Rule> = rules.iter().copied().filter(|r| r.spatial).collect();
        let mut edges = Vec::new();
        for (i, a) in rules.iter().enumerate() {
            for (j, b) in rules.iter().enumerate() {
                let tag = a
                    .outputs
                    .iter()
                    .find(|o| b.shape_tags.iter().any(|t| t.name == o.name))
                    .map(|o| o.name.clone());
                if let Some(tag) = tag {
                    edges.push((i, j, tag));
                }
            }
        }
        let levels = levels(rules.len(), &edges);
        Graph {
            rules,
            edges,
            levels,
        }
    }

    /// Node, edge and depth counts.
    pub fn stats(&self) -> GraphStats {
        GraphStats {
            nodes: self.rules.len(),
            edges: self.edges.len(),
            depth: self.levels.iter().map(|l| l + 1).max().unwrap_or(0),
        }
    }
}

/// Strongly connected components (Tarjan, iterative); returns each node's component, with
/// components numbered in reverse topological order.
fn components(n: usize, adj: &[Vec<usize>]) -> Vec<usize> {
    let mut index = vec![usize::MAX; n];
    let mut low = vec![0; n];
    let mut on_stack = vec![false; n];
    let mut comp = vec![usize::MAX; n];
    let mut stack = Vec::new();
    let mut next = 0;
    let mut count = 0;
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        let mut work = vec![(root, 0usize)];
        while let Some(&mut (v, ref mut k)) = work.last_mut() {
            if *k == 0 {
                index[v] = next;
                low[v] = next;
                next += 1;
                stack.push(v);
                on_stack[v] = true;
            }
            if let Some(&w) = adj[v].get(*k) {
                *k += 1;
                if index[w] == usize::MAX {
                    work.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            work.pop();
            if let Some(&(u, _)) = work.last() {
                low[u] = low[u].min(low[v]);
            }
            if low[v] == index[v] {
                while let Some(w) = stack.pop() {
                    on_stack[w] = false;
                    comp[w] = count;
                    if w == v {
                        break;
                    }
                }
                count += 1;
            }
        }
    }
    comp
}

/// Longest-path levels over the graph with cycles collapsed.
fn levels(n: usize, edges: &[(usize, usize, String)]) -> Vec<usize> {
    let mut adj = vec![Vec::new(); n];
    for (a, b, _) in edges {
        adj[*a].push(*b);
    }
    let comp = components(n, &adj);
    let ncomp = comp.iter().map(|c| c + 1).max().unwrap_or(0);
    // Tarjan numbers components in reverse topological order: feeders get higher numbers.
    let mut level = vec![0usize; ncomp];
    for c in (0..ncomp).rev() {
        for v in (0..n).filter(|&v| comp[v] == c) {
            for &w in &adj[v] {
                if comp[w] != c {
                    level[comp[w]] = level[comp[w]].max(level[c] + 1);
                }
            }
        }
    }
    comp.iter().map(|&c| level[c]).collect()
}

/// Size and depth of the grammar graph of `rules` (spatial rules only).
pub fn graph_stats(rules: &[&Rule]) -> GraphStats {
    Graph::new(rules).stats()
}

/// An expression as source-like text, for labels.
fn expr_text(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Num(v) => format!("{v}"),
        ExprKind::Str(s) => {
            let short: String = s.chars().take(16).collect();
            if short.len() < s.len() {
                format!("\"{short}…\"")
            } else {
                format!("\"{s}\"")
            }
        }
        ExprKind::Color(c) => c.to_hex(),
        ExprKind::Ident(n) => n.clone(),
        ExprKind::Call { name, args } => {
            format!(
                "{name}({})",
                args.iter()
                    .map(|a| expr_text(&a.value))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
        ExprKind::Tuple(items) => format!(
            "({})",
            items.iter().map(expr_text).collect::<Vec<_>>().join(", ")
        ),
        ExprKind::Neg(x) => format!("-{}", expr_text(x)),
        ExprKind::Binary { op, lhs, rhs } => {
            format!("{} {} {}", expr_text(lhs), op.symbol(), expr_text(rhs))
        }
        ExprKind::Size(c, r, 2) => format!("{c}x{r}"),
        ExprKind::Size(c, r, p) => format!("{c}x{r}x{p}"),
    }
}

/// A rule's two label lines: the operator call, and its tags.
fn label(rule: &Rule) -> (String, String) {
    let args: Vec<String> = rule
        .args
        .iter()
        .map(|a| match &a.name {
            Some(n) => format!("{n}={}", expr_text(&a.value)),
            None => expr_text(&a.value),
        })
        .collect();
    let tags = |ts: &[crate::grammar::ast::TagRef]| {
        ts.iter()
            .map(|t| t.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    (
        format!("{}({})", rule.op, args.join(", ")),
        format!("{} → {}", tags(&rule.shape_tags), tags(&rule.outputs)),
    )
}

/// Text for a DOT string.
fn dot_escape(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

/// Text for SVG character data.
fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The grammar graph in Graphviz DOT.
pub fn graph_dot(rules: &[&Rule]) -> String {
    let g = Graph::new(rules);
    let mut out = String::from(
        "digraph grammar {\n  rankdir=TB;\n  node [shape=box, fontname=\"Helvetica\"];\n",
    );
    for (i, r) in g.rules.iter().enumerate() {
        let (call, tags) = label(r);
        let _ = writeln!(
            out,
            "  r{i} [label=\"{}\\n{}\"];",
            dot_escape(&call),
            dot_escape(&tags)
        );
    }
    for (a, b, tag) in &g.edges {
        let _ = writeln!(out, "  r{a} -> r{b} [label=\"{}\"];", dot_escape(tag));
    }
    out.push_str("}\n");
    out
}

/// The grammar graph as a standalone SVG: rules in rows by level, edges as arrows (those
/// running back up a level, or from a rule to itself, curve round the side).
pub fn graph_svg(rules: &[&Rule]) -> String {
    const CHAR_W: f64 = 7.0;
    const BOX_H: f64 = 38.0;
    const ROW: f64 = 80.0;
    const GAP: f64 = 24.0;
    const MARGIN: f64 = 20.0;
    let g = Graph::new(rules);
    let labels: Vec<(String, String)> = g.rules.iter().map(|r| label(r)).collect();
    let widths: Vec<f64> = labels
        .iter()
        .map(|(a, b)| a.chars().count().max(b.chars().count()) as f64 * CHAR_W + 16.0)
        .collect();
    let depth = g.stats().depth;
    let mut rows: Vec<Vec<usize>> = vec![Vec::new(); depth];
    for (i, &l) in g.levels.iter().enumerate() {
        rows[l].push(i);
    }
    let row_width = |row: &Vec<usize>| {
        row.iter().map(|&i| widths[i]).sum::<f64>() + GAP * row.len().saturating_sub(1) as f64
    };
    let width = rows.iter().map(row_width).fold(200.0, f64::max) + 2.0 * MARGIN;
    let height = depth as f64 * ROW - (ROW - BOX_H) + 2.0 * MARGIN;
    let mut pos = vec![(0.0, 0.0); g.rules.len()];
    for (l, row) in rows.iter_mut().enumerate() {
        // Each rule under the mean centre of the rules feeding it (grammar order among
        // equals, and for rules fed by nothing), which keeps most edges short and uncrossed.
        let key = |i: usize| {
            let feeders: Vec<f64> = g
                .edges
                .iter()
                .filter(|(a, b, _)| *b == i && g.levels[*a] < l)
                .map(|(a, _, _)| pos[*a].0 + widths[*a] / 2.0)
                .collect();
            if feeders.is_empty() {
                f64::INFINITY
            } else {
                feeders.iter().sum::<f64>() / feeders.len() as f64
            }
        };
        row.sort_by(|&a, &b| key(a).total_cmp(&key(b)).then(a.cmp(&b)));
        let mut x = (width - row_width(row)) / 2.0;
        for &i in row.iter() {
            pos[i] = (x, MARGIN + l as f64 * ROW);
            x += widths[i] + GAP;
        }
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="Helvetica, Arial, 'DejaVu Sans', sans-serif" font-size="12">
<defs><marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse"><path d="M0 0 L10 5 L0 10 z" fill="#555"/></marker></defs>
<rect width="100%" height="100%" fill="white"/>"##
    );
    for (a, b, _) in &g.edges {
        let (ax, ay) = pos[*a];
        let (bx, by) = pos[*b];
        let (acx, bcx) = (ax + widths[*a] / 2.0, bx + widths[*b] / 2.0);
        if g.levels[*b] > g.levels[*a] {
            let _ = writeln!(
                out,
                r##"<path d="M{acx:.1} {:.1} C {acx:.1} {:.1} {bcx:.1} {:.1} {bcx:.1} {by:.1}" fill="none" stroke="#555" marker-end="url(#arrow)"/>"##,
                ay + BOX_H,
                ay + BOX_H + 30.0,
                by - 30.0
            );
        } else {
            // Back or self edge: a loop out of the source's right side into the target's.
            let (sx, sy) = (ax + widths[*a], ay + BOX_H / 2.0);
            let (tx, ty) = (bx + widths[*b], by + BOX_H / 2.0 - 6.0);
            let bulge = sx.max(tx) + 30.0;
            let _ = writeln!(
                out,
                r##"<path d="M{sx:.1} {sy:.1} C {bulge:.1} {sy:.1} {bulge:.1} {ty:.1} {tx:.1} {ty:.1}" fill="none" stroke="#a33" stroke-dasharray="4 3" marker-end="url(#arrow)"/>"##
            );
        }
    }
    for (i, (call, tags)) in labels.iter().enumerate() {
        let (x, y) = pos[i];
        let w = widths[i];
        let _ = writeln!(
            out,
            r##"<g><rect x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{BOX_H}" rx="4" fill="#f4f4f0" stroke="#333"/><text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text><text x="{:.1}" y="{:.1}" text-anchor="middle" fill="#555">{}</text></g>"##,
            x + w / 2.0,
            y + 16.0,
            xml_escape(call),
            x + w / 2.0,
            y + 31.0,
            xml_escape(tags)
        );
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rules(src: &str) -> Vec<Rule> {
        crate::grammar::parse(src)
            .expect("test grammar parses")
            .rules
    }

    /// gTangle's Fig. 9 leaf grammar.
    const LEAF: &str = "outline(25) : big_poly -> [in, out]
place(20, 25) : out -> [blob, rem]
regularSplit(line, 90, 1) : in -> [quads]
regroup(2) : quads -> [ung_quads]
outline(7) : ung_quads -> [in_2, out_2]
outline(5) : in_2 -> [in_3, out_3]
stipling() : in_3 -> [term, term]
regularSplit(line, 50, 0) : ung_quads -> [slices]
regroup(2) : slices -> [reg_slices]
regularSplit(line, 10, 0) : reg_slices -> [final]
outline(3) : final -> [tiny, tiny_out]
invert() : rem -> [term]
";

    #[test]
    fn leaf_grammar_graph() {
        let rs = rules(LEAF);
        let refs: Vec<&Rule> = rs.iter().collect();
        // Edges: 1→2, 1→3, 2→12, 3→4, 4→5, 4→8, 5→6, 6→7, 8→9, 9→10, 10→11.
        assert_eq!(
            graph_stats(&refs),
            GraphStats {
                nodes: 12,
                edges: 11,
                depth: 7
            }
        );
        let dot = graph_dot(&refs);
        assert!(dot.contains("r0 -> r1 [label=\"out\"]"), "{dot}");
        assert!(dot.contains("regularSplit(line, 90, 1)"));
        let svg = graph_svg(&refs);
        assert_eq!(svg.matches("<rect x=").count(), 12);
        assert_eq!(svg.matches("marker-end").count(), 11);
        assert!(usvg::Tree::from_str(&svg, &usvg::Options::default()).is_ok());
    }

    #[test]
    fn cycles_count_once_and_timeslice_rules_are_ignored() {
        let rs = rules(
            "outline(2) : a -> [c, b]\nregroup(2) : b -> [a]\nfill(red) : c -> [d]\nanimate(affine, local, 0, scale(2)) : [all, d] -> [t]\n",
        );
        let refs: Vec<&Rule> = rs.iter().collect();
        // a ⇄ b is one level, then fill: depth 2.
        assert_eq!(
            graph_stats(&refs),
            GraphStats {
                nodes: 3,
                edges: 3,
                depth: 2
            }
        );
        assert_eq!(graph_stats(&[]), GraphStats::default());
    }
}
