//! Live scene: polls the scene file's modification time and size; on a change, loads it with
//! the server's options and tells the page (server-sent event `scene`): a new version, or the
//! error (file, JSON path, message) while the last good image stays.

use super::state::{lock, stamp, State};
use std::sync::Arc;
use std::time::Duration;

/// How often the file is looked at.
pub const POLL: Duration = Duration::from_millis(250);

pub async fn run(state: Arc<State>) {
    let mut last = stamp(&state.scene_path);
    loop {
        tokio::time::sleep(POLL).await;
        let now = stamp(&state.scene_path);
        if now == last {
            continue;
        }
        last = now;
        let st = state.clone();
        let loaded = tokio::task::spawn_blocking(move || st.scene(&[]).map(|_| ())).await;
        let error = match loaded {
            Ok(Ok(())) => None,
            Ok(Err(e)) => Some(format!("error: {e}")),
            Err(_) => Some("error: loading the scene failed unexpectedly".to_string()),
        };
        let status = {
            let mut s = lock(&state.status);
            if error.is_none() {
                s.version += 1;
            }
            s.error = error;
            s.clone()
        };
        let _ = state
            .events
            .send(serde_json::to_string(&status).unwrap_or_default());
    }
}
