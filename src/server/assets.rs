//! The page, embedded in the binary: one HTML file, its stylesheet and its script. Nothing is
//! fetched at run time and no request path reaches the file system: a path is one of these
//! three names or a 404.

const INDEX: &str = include_str!("page/index.html");
const CSS: &str = include_str!("page/page.css");
const JS: &str = include_str!("page/page.js");

/// The asset at `path`: (content type, body).
pub fn get(path: &str) -> Option<(&'static str, &'static str)> {
    match path {
        "/" | "/index.html" => Some(("text/html; charset=utf-8", INDEX)),
        "/page.css" => Some(("text/css; charset=utf-8", CSS)),
        "/page.js" => Some(("text/javascript; charset=utf-8", JS)),
        _ => None,
    }
}
