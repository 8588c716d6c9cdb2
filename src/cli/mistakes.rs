//! `rtlab mistakes`: the catalogue of deliberate mistakes (`--mistake NAME`), each with what
//! the wrong code does and the formula of the lecture it breaks.

use crate::error::{Error, Result};
use crate::mistakes::Mistake;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output format: text or json (`[{"name", "does", "breaks"}]`).
    #[arg(long, default_value = "text", value_name = "text|json")]
    pub format: String,
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    let text = match args.format.as_str() {
        "text" => {
            let mut t = String::new();
            for m in Mistake::ALL {
                t += &format!(
                    "{}\n    {}\n    breaks: {}\n",
                    m.name(),
                    m.does(),
                    m.breaks()
                );
            }
            t
        }
        "json" => {
            let list: Vec<serde_json::Value> = Mistake::ALL
                .iter()
                .map(|m| serde_json::json!({"name": m.name(), "does": m.does(), "breaks": m.breaks()}))
                .collect();
            serde_json::to_string_pretty(&list).expect("plain JSON") + "\n"
        }
        f => {
            return Err(Error::arg(
                "--format",
                format!("unknown format \"{f}\" (expected text or json)"),
            ))
        }
    };
    super::emit(out, &text)
}
