//! The backend contract (`backend-contract`) on the float backend: every answer satisfies its
//! defining equation to a relative `1e-8` (the default rank tolerance is `1e-10`).

use backend_contract::{backend_tests, Contract};
use float_qr::FloatQr;

backend_tests!(float: FloatQr::default(), Contract::float(1e-8));
