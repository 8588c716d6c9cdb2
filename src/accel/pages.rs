//! Big arrays on huge pages. A ray's walk down a big mesh's BVH touches a node or a leaf's
//! faces on a different 4 KiB page at almost every step; the processor's table of recently
//! used pages (the TLB) holds far fewer pages than a million-triangle mesh spans, so each
//! step waits for the page table as well as for the memory. Linux backs a region with 2 MiB
//! pages when the program asks (`madvise(MADV_HUGEPAGE)`, "transparent huge pages"), and
//! Embree asks for its BVH: so do we, for the arrays rays walk (nodes, leaf order, faces).
//! Contents, results and bytes written never change; only how the kernel maps the memory.
//! Elsewhere than Linux, and where the kernel says no, nothing happens.
#![allow(unsafe_code)]

/// Below this many bytes an array stays on ordinary pages (it spans a few TLB entries).
const HUGE_MIN: usize = 4 << 20;
/// The size of a huge page on x86-64 and aarch64 Linux.
const HUGE: usize = 2 << 20;

/// An empty vector with room for `capacity` items, its whole 2 MiB stretches of memory
/// marked for huge pages before anything is written to them (pages are given at the first
/// write: marking memory already written changes nothing until the kernel's background
/// collapse gets there).
pub fn vec_on_huge_pages<T>(capacity: usize) -> Vec<T> {
    let v: Vec<T> = Vec::with_capacity(capacity);
    let bytes = v.capacity() * std::mem::size_of::<T>();
    if bytes >= HUGE_MIN {
        advise(v.as_ptr() as usize, bytes);
    }
    v
}

#[cfg(target_os = "linux")]
fn advise(start: usize, bytes: usize) {
    // Only whole huge pages inside the allocation: madvise wants a page-aligned start, and
    // a huge page straddling the allocation's ends would not be ours alone.
    let first = start.next_multiple_of(HUGE);
    let end = (start + bytes) / HUGE * HUGE;
    if end > first {
        // SAFETY: [first, end) lies inside the vector's own allocation, which is live and
        // not yet written; MADV_HUGEPAGE changes how the kernel maps those pages, never
        // their contents, so no Rust value can observe it. A refusal (no THP) is ignored.
        unsafe {
            libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_start: usize, _bytes: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vector made for huge pages has the room asked for and takes items as any other.
    #[test]
    fn vectors_on_huge_pages_hold_their_items() {
        for n in [0, 1, 1000, 3 << 20] {
            let items: Vec<u32> = (0..n as u32).map(|i| i.wrapping_mul(2654435761)).collect();
            let mut v = vec_on_huge_pages(n);
            assert!(v.is_empty() && v.capacity() >= n, "{n} items");
            v.extend_from_slice(&items);
            assert_eq!(v, items, "{n} items");
        }
    }
}
