//! What a command that failed says, and with which exit status.

use std::fmt;
use std::process::ExitCode;

/// A failed command: bad input (exit status 2) or a processing failure (exit status 1).
#[derive(Debug)]
pub enum Failure {
    /// A missing or malformed file, a bad option value: the user's to fix.
    BadInput(anyhow::Error),
    /// The input was fine but the work failed: no GPU, a write error.
    Processing(anyhow::Error),
}

impl Failure {
    /// The process exit status for this failure.
    #[must_use]
    pub(crate) fn exit_code(&self) -> ExitCode {
        match self {
            Self::BadInput(_) => ExitCode::from(2),
            Self::Processing(_) => ExitCode::from(1),
        }
    }

    /// A bad-input failure with this message.
    pub(crate) fn input(message: impl fmt::Display) -> Self {
        Self::BadInput(anyhow::anyhow!("{message}"))
    }

    /// A processing failure with this message.
    pub(crate) fn processing(message: impl fmt::Display) -> Self {
        Self::Processing(anyhow::anyhow!("{message}"))
    }

    /// Whether the input was at fault.
    #[must_use]
    pub(crate) fn is_bad_input(&self) -> bool {
        matches!(self, Self::BadInput(_))
    }
}

impl fmt::Display for Failure {
    /// One line: the error and its causes joined by ": ", newlines folded. A cause whose text
    /// the line already holds is left out (library errors often print their source in their
    /// own message, `path: what the OS said`, and the chain would say it twice).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (Self::BadInput(e) | Self::Processing(e)) = self;
        let mut text = String::new();
        for cause in e.chain() {
            let part = cause.to_string();
            if text.contains(&part) {
                continue;
            }
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&part);
        }
        let one_line: Vec<&str> = text.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
        f.write_str(&one_line.join(" "))
    }
}

/// Turns library errors into [`Failure`]s.
pub trait Classify<T> {
    /// The error is the input's fault (exit status 2).
    ///
    /// # Errors
    /// The error, classified.
    fn bad_input(self) -> Result<T, Failure>;
    /// The error is a processing failure (exit status 1).
    ///
    /// # Errors
    /// The error, classified.
    fn processing(self) -> Result<T, Failure>;
}

impl<T, E: Into<anyhow::Error>> Classify<T> for Result<T, E> {
    fn bad_input(self) -> Result<T, Failure> {
        self.map_err(|e| Failure::BadInput(e.into()))
    }
    fn processing(self) -> Result<T, Failure> {
        self.map_err(|e| Failure::Processing(e.into()))
    }
}
