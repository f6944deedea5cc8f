//! Subcommands of `vifo`, one module each.
