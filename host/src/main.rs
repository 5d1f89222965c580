//! The `stoss` binary.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Output piped into a reader that stops early (`stoss simulate ... | head`): Rust ignores
    // SIGPIPE, so printing then fails with EPIPE and `println!` panics. End quietly instead,
    // with the status a shell gives a process killed by SIGPIPE (128 + 13).
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or_default();
        if message.starts_with("failed printing to stdout") && message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default_hook(info);
    }));
    stoss::cli::run(stoss::cli::Cli::parse())
}
