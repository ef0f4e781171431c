//! Helpers shared by the test modules.

use std::process::{Command, Output};

/// The `rocklab` binary under test, ready for arguments.
pub fn rocklab_command(args: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rocklab"));
    cmd.args(args);
    cmd
}

/// Run the `rocklab` binary with `args` and collect its output.
pub fn rocklab(args: &[&str]) -> Output {
    rocklab_command(args).output().expect("rocklab runs")
}
