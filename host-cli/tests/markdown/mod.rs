//! Markdown as the documentation tests read it: fenced blocks with their
//! info strings, and the prose between them.

#![allow(
    dead_code,
    reason = "each test that includes this module uses what it needs of it"
)]

/// A fenced block: its info string, its lines and the line (1-based) of
/// its opening fence.
pub struct Block {
    pub info: String,
    pub lines: Vec<String>,
    pub line: usize,
}

/// The fenced blocks of `markdown`, in order.
pub fn blocks(markdown: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    let mut open: Option<Block> = None;
    for (number, line) in markdown.lines().enumerate() {
        match (&mut open, line.strip_prefix("```")) {
            (None, Some(info)) => {
                open = Some(Block {
                    info: info.trim().to_string(),
                    lines: Vec::new(),
                    line: number + 1,
                });
            }
            (Some(_), Some(_)) => blocks.extend(open.take()),
            (Some(block), None) => block.lines.push(line.to_string()),
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "a block is never closed");
    blocks
}

/// The prose of `markdown`: every line outside fenced blocks, each with
/// its line number (1-based).
pub fn prose(markdown: &str) -> Vec<(usize, &str)> {
    let mut inside = false;
    let mut lines = Vec::new();
    for (number, line) in markdown.lines().enumerate() {
        if line.starts_with("```") {
            inside = !inside;
        } else if !inside {
            lines.push((number + 1, line));
        }
    }
    lines
}
