//! The grammar parser and checker, as `gmotion check GRAMMAR` runs them: any bytes, read as
//! the command reads a grammar file (UTF-8, byte-order mark, line endings), parsed, its
//! directives and static errors checked, every diagnostic rendered with its source line.
#![no_main]

use gmotion::engine::{self, EngineError, RunOptions};
use gmotion::grammar::{self, Diagnostic};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(src) = gmotion::input::utf8_text(data.to_vec()) else {
        return;
    };
    let g = match grammar::parse(&src) {
        Ok(g) => g,
        Err(d) => {
            let _ = d.render("g.gm", &src);
            return;
        }
    };
    let render = |e: &EngineError| {
        if let Some(span) = e.span {
            let _ = Diagnostic::new(span, e.message.clone()).render("g.gm", &src);
        }
    };
    if let Err(e) = engine::settings::from_grammar(&g) {
        render(&e);
        return;
    }
    let errors = engine::check::static_errors(&g);
    errors.iter().for_each(render);
    if errors.is_empty()
        && let Err(e) = engine::check::check(&g, None, &RunOptions::default())
    {
        render(&e);
    }
});
