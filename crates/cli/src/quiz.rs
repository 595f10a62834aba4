//! `accelviz-cli quiz`: questions made from a seed by the quiz engine the app's quiz mode
//! runs, as text for a lecturer to print (answers and explanations included) or as JSON, one
//! object per line, for checking and for other tools.

use accelviz_quiz::{Level, Session, kind_names};
use anyhow::{Context, Result, bail};
use clap::Args;

/// `--kind`'s help: every kind of question.
fn kind_help() -> String {
    format!(
        "The kind of question, one of {}; every kind in turn when not given",
        kind_names().join(", ")
    )
}

#[derive(Args, Debug)]
pub struct QuizArgs {
    #[arg(long, help = kind_help())]
    kind: Option<String>,
    /// The seed: the same seed gives the same questions here, in the app and in the browser.
    #[arg(long, allow_hyphen_values = true)]
    seed: String,
    /// How many questions (question i is made from seed + i).
    #[arg(long, default_value = "1", allow_hyphen_values = true)]
    count: String,
    /// easy (a few shapes, round numbers), medium or hard (more shapes, the slab test in 3D).
    #[arg(long, default_value = "easy")]
    level: String,
    /// One JSON object per question, one per line.
    #[arg(long)]
    json: bool,
}

/// The most questions one call makes.
const MOST_QUESTIONS: usize = 10_000;

pub fn run(args: &QuizArgs) -> Result<String> {
    let seed: u64 = args.seed.trim().parse().with_context(|| {
        format!(
            "--seed: '{}' is not a whole number from 0 to {}",
            args.seed,
            u64::MAX
        )
    })?;
    let count: usize = args
        .count
        .trim()
        .parse()
        .ok()
        .filter(|count| (1..=MOST_QUESTIONS).contains(count))
        .with_context(|| {
            format!(
                "--count: '{}' is not a whole number from 1 to {MOST_QUESTIONS}",
                args.count
            )
        })?;
    let level = Level::parse(&args.level).map_err(|error| anyhow::anyhow!("--level: {error}"))?;
    let kinds: Vec<&str> = args.kind.as_deref().into_iter().collect();
    if let Some(kind) = &args.kind
        && !kind_names().contains(&kind.as_str())
    {
        bail!(
            "--kind: unknown question kind '{kind}'; the kinds are: {}",
            kind_names().join(", ")
        );
    }
    let session = Session::new(seed, level, count, &kinds)?;
    let mut output = String::new();
    for (index, question) in session.questions().iter().enumerate() {
        if args.json {
            output.push_str(&question.to_json());
        } else {
            if index > 0 {
                output.push('\n');
            }
            output.push_str(&question.to_text());
        }
        if args.json {
            output.push('\n');
        }
    }
    Ok(output)
}
