// What every test page imports: report a result to the driver (run.mjs) and stop.
// `finish(result)` sets window.__result and window.__done; `run(fn)` awaits fn() and
// reports its value, or { ok: false, error } when it throws.
export function finish(result) {
  window.__result = result;
  window.__done = true;
}

export async function run(fn) {
  try {
    finish(await fn());
  } catch (e) {
    finish({ ok: false, error: String(e && e.stack ? e.stack : e) });
  }
}
