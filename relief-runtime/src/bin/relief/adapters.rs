//! `relief adapters`: the adapters wgpu sees, and the one relief would use.

use relief_runtime::gpu::{adapters, choose, ADAPTER_VAR};

/// Prints each adapter (name, backend, device type, driver) and marks the one `render`,
/// `sweep`, `stability` and `room` would use (`--adapter` / `RELIEF_ADAPTER`, else hardware
/// first).
pub fn run() -> anyhow::Result<()> {
    let infos = adapters();
    if infos.is_empty() {
        anyhow::bail!("wgpu sees no adapter; on Linux without a GPU, install Mesa's software Vulkan device: `apt-get install mesa-vulkan-drivers libvulkan1`");
    }
    let wanted = std::env::var(ADAPTER_VAR).ok().filter(|w| !w.trim().is_empty());
    let chosen = choose(&infos, wanted.as_deref()).ok();
    for (i, a) in infos.iter().enumerate() {
        let mark = if Some(i) == chosen { "*" } else { " " };
        let driver = format!("{} {}", a.driver, a.driver_info);
        println!("{mark} {}  backend {:?}, type {:?}, driver {}", a.name, a.backend, a.device_type, driver.trim());
    }
    match (chosen, wanted) {
        (Some(_), Some(w)) => println!("* the adapter matching `{w}` ({ADAPTER_VAR} / --adapter)"),
        (Some(_), None) => {
            println!("* the adapter used (hardware preferred; pick another with --adapter SUBSTRING or {ADAPTER_VAR})")
        }
        (None, Some(w)) => anyhow::bail!("no adapter matches `{w}` (--adapter / {ADAPTER_VAR})"),
        (None, None) => {}
    }
    Ok(())
}
