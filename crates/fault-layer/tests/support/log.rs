//! The library's log, collected: validation messages arrive there as they are raised (also
//! those of a device torn down inside a failed constructor, which no caller can ask for), and
//! so do leaks ("dropped without destroy()").

use std::sync::Mutex;

static RECORDS: Mutex<Vec<String>> = Mutex::new(Vec::new());

struct Collector;

impl log::Log for Collector {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::Level::Warn
    }

    fn log(&self, record: &log::Record) {
        if self.enabled(record.metadata()) {
            let text = record.args().to_string();
            RECORDS.lock().unwrap_or_else(|p| p.into_inner()).push(text);
        }
    }

    fn flush(&self) {}
}

/// Collects the library's warnings and errors from now on.
pub fn install() {
    static COLLECTOR: Collector = Collector;
    if log::set_logger(&COLLECTOR).is_ok() {
        log::set_max_level(log::LevelFilter::Warn);
    }
}

/// The validation messages and leaks logged since the last call (the loader's notes on the
/// layers the environment enables are neither).
pub fn take_problems() -> Vec<String> {
    let records = std::mem::take(&mut *RECORDS.lock().unwrap_or_else(|p| p.into_inner()));
    records
        .into_iter()
        .filter(|r| {
            let validation = r.starts_with('[') && !r.contains("Loader Message");
            validation || r.contains("leak")
        })
        .collect()
}
