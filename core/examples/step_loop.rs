//! N steps of one method on one system from its first preset, nothing else: what
//! `bench/fast_path_instructions.sh` counts under callgrind (instructions per step are the
//! difference between two step counts, so that setting up and exiting cancel).
//!
//! `step_loop SYSTEM METHOD PATH STEPS`: METHOD is an index into `Method::all()` (the paper's
//! five, then the others), PATH `fast` (the method's default) or `general`; `step_loop list`
//! prints the indices and which have a general path.

use nhlab_core::BuiltIn;
use nhlab_core::{Method, State, Vector, for_each_system};

fn run<S: BuiltIn<N, R>, const N: usize, const R: usize>(system: &str, m: &Method, steps: u64) {
    if S::info().id != system {
        return;
    }
    let p = &S::info().presets[0];
    let sys = S::new(&S::info().preset_params(p));
    let (q, v) = (Vector::<N>::from_column_slice(p.q), Vector::<N>::from_column_slice(p.v));
    let mut st = State::with_continuous_multiplier(&sys, q, v).expect("a preset is regular");
    m.steps(&sys, &mut st, p.step, steps).expect("the preset runs");
    println!("{} on {system}: q = {:?}", m.label(), st.q.as_slice());
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
    let [system, method, path, steps] = args.as_slice() else {
        return Err("usage: step_loop SYSTEM METHOD PATH STEPS | step_loop list".into());
    };
    let m = all.get(method.parse::<usize>()?).ok_or("no such method index")?;
    let m = match path.as_str() {
        "fast" => *m,
        "general" => m.general_path().ok_or("this method has no general path")?,
        _ => return Err("PATH is fast or general".into()),
    };
    for_each_system!(run, system, &m, steps.parse()?);
    Ok(())
}
