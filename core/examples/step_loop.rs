//! N steps of one method on one system from its first preset, nothing else: what
//! `bench/fast_path_instructions.sh` counts under callgrind (instructions per step are the
//! difference between two step counts, so that setting up and exiting cancel).
//!
//! `step_loop SYSTEM METHOD PATH STEPS [PRESET]`: METHOD is an index into `Method::all()` (the
//! paper's five, then the others), PATH `fast` (the method's default), `general`, or
//! `formulas` (the default path on the system given as formulas, `FormulaSpec::of`); PRESET an
//! index into the system's presets (0 if left out). `step_loop list` prints the indices and
//! which methods have a general path.

use nhlab_core::model::custom::Custom;
use nhlab_core::{BuiltIn, CustomLimits, CustomSystem, FormulaSpec, Preset, System};
use nhlab_core::{Method, State, Vector, for_each_system};

/// What runs: the method, whether on the system given as formulas, the preset, the steps.
struct Run {
    method: Method,
    formulas: bool,
    preset: usize,
    steps: u64,
}

fn run<S: BuiltIn<N, R>, const N: usize, const R: usize>(system: &str, run: &Run) {
    let info = S::info();
    if info.id != system {
        return;
    }
    let Some(p) = info.presets.get(run.preset) else {
        eprintln!("{system} has {} presets, numbered from 0", info.presets.len());
        std::process::exit(2);
    };
    let sys = S::new(&info.preset_params(p));
    if run.formulas {
        let overrides: Vec<_> = p.params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
        let compiled = CustomSystem::compile(
            &FormulaSpec::of(info).expect("a class built-in"),
            &overrides,
            &CustomLimits::default(),
        )
        .expect("a built-in's formula form compiles");
        steps_on(
            &Custom::<N, R>::new(compiled.class_compiled().expect("the class").clone()),
            p,
            run,
        );
    } else {
        steps_on(&sys, p, run);
    }
}

fn steps_on<S: System<N, R>, const N: usize, const R: usize>(sys: &S, p: &Preset, run: &Run) {
    let (q, v) = (Vector::<N>::from_column_slice(p.q), Vector::<N>::from_column_slice(p.v));
    let mut st = State::with_continuous_multiplier(sys, q, v).expect("a preset is regular");
    run.method.steps(sys, &mut st, p.step, run.steps).expect("the preset runs");
    println!("{} on {}: q = {:?}", run.method.label(), p.id, st.q.as_slice());
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let all = Method::all();
    if args.first().map(String::as_str) == Some("list") {
        for (i, m) in all.iter().enumerate() {
            println!("{i} {} {}", m.label().replace(' ', "_"), m.general_path().is_some());
        }
        return Ok(());
    }
    let (system, method, path, steps, preset) = match args.as_slice() {
        [s, m, p, n] => (s, m, p, n, "0"),
        [s, m, p, n, preset] => (s, m, p, n, preset.as_str()),
        _ => {
            return Err(
                "usage: step_loop SYSTEM METHOD PATH STEPS [PRESET] | step_loop list".into()
            );
        }
    };
    let m = all.get(method.parse::<usize>()?).ok_or("no such method index")?;
    let method = match path.as_str() {
        "fast" | "formulas" => *m,
        "general" => m.general_path().ok_or("this method has no general path")?,
        _ => return Err("PATH is fast, general or formulas".into()),
    };
    let r = Run {
        method,
        formulas: path == "formulas",
        preset: preset.parse()?,
        steps: steps.parse()?,
    };
    for_each_system!(run, system, &r);
    Ok(())
}
