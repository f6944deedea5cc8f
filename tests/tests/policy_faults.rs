//! A misbehaving policy server (`vifo_tests::fault_server`): each fault ends the episode it
//! hits as an error naming the fault, the run goes on, the resumed run retries the episode,
//! and nothing written before is lost. (`examples/policy_faults.rs` repeats this 10 times per
//! fault and prints the counts.) Two client defects this found are fixed: a malformed reply
//! kept the connection (so a confused server kept serving the next episode), and metadata that
//! was not one msgpack map (`0xc1` decodes as nil) passed the handshake.

use vifo_tests::fault_server::Fault;
use vifo_tests::fault_trials::{Counts, run_faults};

#[test]
fn every_fault_is_an_error_naming_it_and_the_run_recovers() {
    let dir = tempfile::tempdir().unwrap();
    let c = run_faults(&Fault::ALL, 1, dir.path()).unwrap();
    let n = Fault::ALL.len();
    let expected = Counts { episodes: n + 1, fired: n, errors_named: n, ..Counts::default() };
    assert_eq!(c, expected);
}
