//! Collects criterion's estimates (run `cargo bench` first) into data/benchmarks.csv.
use jointwear::error::exit_on_error;
use jointwear::paper::performance::{benchmark_summary, criterion_dir};

fn main() {
    let _claim = jointwear::paper::program::flags(
        "bench_summary",
        "Collects criterion's estimates (run `cargo bench` first) into data/benchmarks.csv",
        &[],
    );
    let results = exit_on_error(benchmark_summary(&criterion_dir()));
    println!(
        "{}",
        jointwear::paper::program::in_root("wrote data/benchmarks.csv")
    );
    println!("{:<34} {:>14} {:>14}", "bench", "median", "MAD");
    for r in &results {
        println!("{:<34} {:>14} {:>14}", r.bench, ns(r.median), ns(r.mad));
    }
}

/// A duration in ns, printed in a readable unit.
fn ns(t: f64) -> String {
    match t {
        t if t >= 1e9 => format!("{:.3} s", t * 1e-9),
        t if t >= 1e6 => format!("{:.3} ms", t * 1e-6),
        t if t >= 1e3 => format!("{:.3} µs", t * 1e-3),
        t => format!("{t:.2} ns"),
    }
}
