//! `relief serve DIR`: a report folder over HTTP on this machine, for a browser that will
//! not read `file://` pages (WebGPU, script files).
//!
//! It answers `GET` and `HEAD` for files inside DIR and nothing else: a request whose path
//! climbs out (`..`), names an absolute path, or reaches a file through a link that leads out
//! of DIR gets 404, as does anything that is not a plain file. It binds 127.0.0.1 unless
//! `--bind` says otherwise. One thread per connection, each with a read timeout, so a client
//! that stalls holds only its own thread.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Component, Path, PathBuf};
use std::time::Duration;

/// Arguments of `relief serve`.
#[derive(clap::Args, Debug)]
pub struct ServeArgs {
    /// The folder to serve (a report folder: `relief report DIR` wrote `DIR/index.html`).
    pub dir: PathBuf,
    /// The port; 0 picks a free one (the printed URL names it).
    #[arg(long, default_value_t = 8000)]
    pub port: u16,
    /// The address to listen on. The default answers this machine only; another address
    /// (`0.0.0.0`) lets other machines read every file in DIR.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: std::net::IpAddr,
}

/// How long a connection may take to send its request.
const READ_TIMEOUT: Duration = Duration::from_secs(10);
/// The longest request head read (request line and headers); longer ones get 431.
const MAX_HEAD: usize = 16 * 1024;

/// Runs `relief serve`: binds, prints the URL, then answers until the process is stopped.
pub fn run(a: &ServeArgs) -> anyhow::Result<()> {
    let root = std::fs::canonicalize(&a.dir).map_err(|e| anyhow::anyhow!("cannot serve {}: {e}", a.dir.display()))?;
    if !root.is_dir() {
        anyhow::bail!("cannot serve {}: not a folder", a.dir.display());
    }
    let listener = TcpListener::bind((a.bind, a.port)).map_err(|e| match e.kind() {
        std::io::ErrorKind::AddrInUse => anyhow::anyhow!(
            "port {} on {} is in use (choose another with --port, or --port 0 for a free one)",
            a.port,
            a.bind
        ),
        _ => anyhow::anyhow!("cannot listen on {}:{}: {e}", a.bind, a.port),
    })?;
    let addr = listener.local_addr()?;
    let host = if addr.is_ipv6() { format!("[{}]", addr.ip()) } else { addr.ip().to_string() };
    let page = if root.join("index.html").is_file() { "" } else { " (no index.html there yet)" };
    println!("serving {} at http://{host}:{}/{page}; Ctrl-C stops", root.display(), addr.port());
    if !addr.ip().is_loopback() {
        eprintln!(
            "relief: warning: listening on {}: other machines can read every file in {}",
            addr.ip(),
            root.display()
        );
    }
    std::io::stdout().flush()?;
    for stream in listener.incoming() {
        let Ok(stream) = stream else { continue };
        let root = root.clone();
        std::thread::spawn(move || {
            // A connection that fails (closed early, timed out) concerns only that client.
            let _ = answer(stream, &root);
        });
    }
    Ok(())
}

/// Reads one request from `stream` and answers it.
fn answer(stream: TcpStream, root: &Path) -> std::io::Result<()> {
    stream.set_read_timeout(Some(READ_TIMEOUT))?;
    stream.set_write_timeout(Some(READ_TIMEOUT))?;
    let mut out = stream.try_clone()?;
    let mut reader = BufReader::new(stream.take(MAX_HEAD as u64 + 1));
    let mut request_line = String::new();
    reader.read_line(&mut request_line)?;
    let mut head = request_line.len();
    // The headers are read (to the blank line) and ignored.
    loop {
        let mut line = String::new();
        let n = reader.read_line(&mut line)?;
        head += n;
        if head > MAX_HEAD {
            return status(&mut out, 431, "Request Header Fields Too Large", false);
        }
        if n == 0 || line == "\r\n" || line == "\n" {
            break;
        }
    }
    let mut parts = request_line.split_whitespace();
    let (Some(method), Some(target)) = (parts.next(), parts.next()) else {
        return status(&mut out, 400, "Bad Request", false);
    };
    let head_only = match method {
        "GET" => false,
        "HEAD" => true,
        _ => return status(&mut out, 405, "Method Not Allowed", false),
    };
    match resolve(root, target) {
        Some(Found::File(file)) => send_file(&mut out, &file, head_only),
        Some(Found::Folder) => {
            // A folder's page links relative to the folder: its URL must end with `/`.
            let path = target.split(['?', '#']).next().unwrap_or("/");
            write!(
                out,
                "HTTP/1.1 301 Moved Permanently\r\nLocation: {path}/\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
            )?;
            out.flush()
        }
        None => status(&mut out, 404, "Not Found", head_only),
    }
}

/// What a request names inside the served folder.
enum Found {
    /// A plain file inside it.
    File(PathBuf),
    /// A folder inside it with an `index.html`, named without the trailing `/`.
    Folder,
}

/// The file inside `root` that request target `target` names, or None (404): the target's
/// path is percent-decoded, must be relative to `/` with only plain names (no `..`, no `.`
/// games, no second leading `/`, no drive or backslash), and its canonical path, links
/// followed, must still lie inside `root` and be a plain file. A folder means its
/// `index.html` (asked for without its trailing `/`: [`Found::Folder`]).
fn resolve(root: &Path, target: &str) -> Option<Found> {
    let path = target.split(['?', '#']).next()?;
    let rel = percent_decode(path.strip_prefix('/')?)?;
    if rel.contains('\\') || rel.contains('\0') || rel.starts_with('/') {
        return None;
    }
    let mut file = root.to_path_buf();
    for part in rel.split('/').filter(|p| !p.is_empty()) {
        let mut comps = Path::new(part).components();
        match (comps.next(), comps.next()) {
            (Some(Component::Normal(name)), None) => file.push(name),
            _ => return None,
        }
    }
    let mut real = std::fs::canonicalize(&file).ok()?;
    let folder = real.is_dir();
    if folder {
        real = std::fs::canonicalize(real.join("index.html")).ok()?;
    }
    if !(real.starts_with(root) && real.is_file()) {
        return None;
    }
    Some(if folder && !path.ends_with('/') { Found::Folder } else { Found::File(real) })
}

/// `%XX` escapes decoded; None when an escape is malformed or the result is not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The media type of a file by its extension (what a report folder holds).
fn media_type(file: &Path) -> &'static str {
    match file.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).as_deref() {
        Some("html" | "htm") => "text/html; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("js" | "mjs") => "text/javascript; charset=utf-8",
        Some("json") => "application/json",
        Some("svg") => "image/svg+xml",
        Some("png") => "image/png",
        Some("jpg" | "jpeg") => "image/jpeg",
        Some("webp") => "image/webp",
        Some("csv") => "text/csv; charset=utf-8",
        Some("md" | "txt" | "jsonl" | "wgsl" | "glsl" | "vert" | "frag" | "comp" | "toml") => {
            "text/plain; charset=utf-8"
        }
        _ => "application/octet-stream",
    }
}

fn send_file(out: &mut TcpStream, file: &Path, head_only: bool) -> std::io::Result<()> {
    let Ok(mut f) = std::fs::File::open(file) else {
        return status(out, 404, "Not Found", head_only);
    };
    let len = f.metadata()?.len();
    write!(
        out,
        "HTTP/1.1 200 OK\r\nContent-Type: {}\r\nContent-Length: {len}\r\nCache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        media_type(file)
    )?;
    if !head_only {
        std::io::copy(&mut f, out)?;
    }
    out.flush()
}

fn status(out: &mut TcpStream, code: u16, reason: &str, head_only: bool) -> std::io::Result<()> {
    let body = format!("{code} {reason}\n");
    write!(out, "HTTP/1.1 {code} {reason}\r\nContent-Type: text/plain; charset=utf-8\r\nContent-Length: {}\r\nConnection: close\r\n\r\n", body.len())?;
    if !head_only {
        out.write_all(body.as_bytes())?;
    }
    out.flush()
}
