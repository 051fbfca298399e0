//! The JSON payloads of the plugin ABI: a plugin decoding any request bytes for any method,
//! and a host decoding any answer bytes with any status. Never a panic.
#![no_main]

use api::{Contribution, OperationPlan, OutputCheck, OutputFile};
use libfuzzer_sys::fuzz_target;
use plugin_abi::dispatch;
use plugin_abi::decode_answer;

fuzz_target!(|data: &[u8]| {
    let Some((&selector, payload)) = data.split_first() else {
        return;
    };
    let method = u32::from(selector % 7);
    // Plugin side: a real source answers the request bytes.
    let mut linear = plugins_linear::LinearSource::new();
    let _ = dispatch(&mut linear, method, payload);
    let mut spline = plugins_spline2d::plugin::Spline2dSource::default();
    let _ = dispatch(&mut spline, method, payload);
    // Host side: the answer bytes under every status.
    let status = i32::from(selector % 5);
    let _ = decode_answer::<Contribution>(status, payload);
    let _ = decode_answer::<OperationPlan>(status, payload);
    let _ = decode_answer::<Vec<OutputFile>>(status, payload);
    let _ = decode_answer::<OutputCheck>(status, payload);
    let _ = decode_answer::<()>(status, payload);
});
