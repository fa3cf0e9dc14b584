//! `summary.md`, the table of reproduced figures: for each figure the thesis's
//! claim, the known reference if any, and each curve's final score with its
//! unit, its 95% confidence interval and its greedy score (or why there is none).

use std::fmt::Write as _;

use super::output::{SummaryFile, ci_text, greedy_text, mean_text};
use super::presets::{Figure, FigureKind};

/// A table cell: `|` escaped.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// The Markdown of `figures`, each with the summaries of its curves in order.
pub fn summary_markdown(figures: &[(&Figure, &[SummaryFile])]) -> String {
    let mut md = String::from(
        "# Reproduced figures\n\n\
         Written by `learnpnp reproduce`; each figure's directory holds its CSV files and plots. \
         A score is the mean return of the evaluation episodes at the last evaluation point \
         (in Keepaway the episode duration, in seconds), averaged over the runs, with its 95% \
         confidence interval over the runs; the greedy score is the return of each run's greedy \
         policy at the end, averaged likewise.\n",
    );
    let verdicts = super::verdict::verdict_markdown(figures);
    if verdicts.lines().count() > 2 {
        md.push_str(
            "\n## Verdict\n\nEach claim of the thesis whose figure was reproduced here, checked on the final \
             scores by the rule beside it (`src/experiment/verdict.rs`); docs/results/RESULTS.md discusses them.\n\n",
        );
        md.push_str(&verdicts);
    }
    for (figure, summaries) in figures {
        let _ = write!(md, "\n## Figure {}: {}\n\n", figure.id, figure.title);
        let _ = writeln!(md, "Thesis: {}\n", figure.claim);
        if let Some(r) = summaries.first().and_then(|s| s.spec.domain.reference()) {
            let _ = writeln!(md, "Reference: {}\n", r.label);
        }
        let (score, greedy) = match figure.kind {
            FigureKind::Bars => ("mean score", "greedy"),
            FigureKind::Curves => ("final score", "greedy policy's score"),
            FigureKind::Traces => ("final score", "greedy policy's score"),
        };
        let _ = writeln!(md, "| curve | {score} | 95% CI | {greedy} | runs | wall time |");
        md.push_str("|---|---|---|---|---|---|\n");
        for s in summaries.iter() {
            let (value, ci) = (mean_text(s), ci_text(s));
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {:.1} s |",
                cell(&s.spec.label),
                value,
                ci,
                cell(&greedy_text(s)),
                s.spec.protocol.runs,
                s.wall_seconds
            );
        }
    }
    md
}
