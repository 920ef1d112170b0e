//! One line that is not an O-word: block delete, its values evaluated, then its block.

use super::super::control;
use super::super::syntax::{BLOCK_DELETE, Block};
use super::FrontEnd;
use crate::diag::Diagnostic;
use crate::dialect::iso::codes;
use crate::ir::ItemKind;
use crate::profile::BlockDelete;
use crate::source::Line;

/// The most words a line's room kept for the next line may have room for (a line of many
/// words does not keep its room).
const SPARE_WORDS: usize = 16;

/// The line's comments as one, taken from it (a line's one comment is moved, not copied).
fn joined(comments: &mut Vec<String>) -> String {
    if comments.len() == 1 {
        comments.pop().unwrap_or_default()
    } else {
        comments.join("; ")
    }
}

/// A block's copy that its words' values are evaluated into (without its expressions,
/// settings and O-word, which stay in the block read).
pub(super) fn evaluated_copy(source: &Block) -> Block {
    Block {
        number: source.number,
        words: source.words.clone(),
        exprs: Vec::new(),
        settings: Vec::new(),
        oword: None,
        comments: source.comments.clone(),
        unread: source.unread.clone(),
        delimiter: source.delimiter,
    }
}

/// The line's block to evaluate its values into, and the block as read when it has
/// expressions or settings to evaluate (`None` for a line that cannot be read). A line read
/// for this run alone and without expressions is taken as it is.
fn evaluated_block(parsed: control::Got<'_>) -> Option<(Option<control::Got<'_>>, Block)> {
    Some(match parsed {
        control::Got::Owned(Some(Ok(block)))
            if block.exprs.is_empty() && block.settings.is_empty() =>
        {
            (
                None,
                Block {
                    oword: None,
                    ..block
                },
            )
        }
        parsed => {
            let Some(Ok(source)) = &*parsed else {
                return None;
            };
            let block = evaluated_copy(source);
            (Some(parsed), block)
        }
    })
}

impl FrontEnd<'_> {
    /// Runs one line that is not an O-word: its values evaluated, its parameter settings
    /// made, then its words.
    pub(super) fn line(
        &mut self,
        line: Line<'_>,
        parsed: control::Got<'_>,
        params: &mut control::Params,
    ) {
        // The line's words get their values here; its expressions stay where they were read.
        let Some((source, mut block)) = evaluated_block(parsed) else {
            return;
        };
        self.evaluated_line(line, source, &mut block, params);
        // The room of its words is the next line's.
        let mut words = std::mem::take(&mut block.words);
        if words.capacity() <= SPARE_WORDS {
            words.clear();
            self.spare_words = words;
        }
    }

    /// [`FrontEnd::line`] of the line's block to evaluate (`source`: the block as read, when
    /// it has expressions or settings).
    fn evaluated_line(
        &mut self,
        line: Line<'_>,
        source: Option<control::Got<'_>>,
        block: &mut Block,
        params: &mut control::Params,
    ) {
        if self.block_deleted(line, block) {
            return;
        }
        if let Some(Some(Ok(source))) = source.as_deref()
            && (!source.exprs.is_empty() || !source.settings.is_empty())
            && let Err(e) = self.evaluate(source, &mut block.words, params)
        {
            self.diag(codes::ISOR_EVAL, line, e.range, e.message, e.help);
            self.stopped = true;
            return;
        }
        // Messages read the parameters as the line's settings leave them.
        for c in &mut block.comments {
            if let Some(text) = self.message(c, params) {
                *c = text;
            }
        }
        self.offset_params = [
            params.numbered[5210],
            params.numbered[5211],
            params.numbered[5213],
        ];
        // A line of a roughing cycle's contour: only its shape counts.
        if self.contour.is_some() {
            self.contour_line(line, block);
            return;
        }
        if self.modal_state(line, block, params) {
            return;
        }
        self.line_items(line, block, params);
    }

    /// A line that starts with `/`: skipped when the block delete switch is on (true; the
    /// first such line is reported), read without its `/` when it is off, and left for
    /// [`FrontEnd::unsupported`] to report when nobody said.
    fn block_deleted(&mut self, line: Line<'_>, block: &mut Block) -> bool {
        let Some(at) = block.unread.iter().position(|u| u.what == BLOCK_DELETE) else {
            return false;
        };
        match self.options.block_delete {
            // The switch is on: LinuxCNC skips the line.
            Some(BlockDelete::On) => {
                self.skipped_lines += 1;
                if self.skipped_lines == 1 {
                    let span = self.r.span(line, block.unread[at].range.clone());
                    self.r.diags.push(
                        Diagnostic::new(
                            codes::ISOR_BLOCK_DELETE,
                            "a line that starts with `/` is skipped: the block delete switch is on",
                        )
                        .at(self.r.src, span)
                        .label("skipped, with every line like it")
                        .help("ncthread reads the program as the machine runs it with block delete on; give --block-delete off for the other run"),
                    );
                }
                return true;
            }
            Some(BlockDelete::Off) => {
                block.unread.remove(at);
            }
            None => {}
        }
        false
    }

    /// The line's items: a `%` delimiter, a line of comments only, or its block; stamped
    /// with the line's number and comment.
    fn line_items(&mut self, line: Line<'_>, block: &mut Block, params: &mut control::Params) {
        let first = self.r.items.len();
        let span = self.r.src.line_span(line);
        if block.delimiter {
            self.push(ItemKind::Delimiter, span);
        } else if block.is_empty() {
            if !block.comments.is_empty() {
                self.push(ItemKind::Comment(joined(&mut block.comments)), span);
            }
            return;
        } else {
            self.block(line, block);
            params.numbered[5210] = self.offset_params[0];
        }
        // A line whose words made no item (G21, G90…) keeps its comment as an item.
        let comment = (!block.comments.is_empty()).then(|| joined(&mut block.comments));
        if self.cycle_call.is_some() {
            // The comment stays on the cycle's rapid, if it made one.
            let pushed = self.r.items.len() > first;
            self.stamp_contour(block.number, if pushed { None } else { comment.clone() });
        }
        self.r
            .stamp_block(first, block.number, comment, span, false);
    }
}
