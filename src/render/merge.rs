//! `sturmray merge`: the whole image from its pieces. Each piece is an EXR
//! with its film state beside it (the exact f64 sums). The pieces must come
//! from one scene and frame, be complete, and tile the image with no gap or
//! overlap; pieces of the same region rendered with different seeds add up to
//! more samples. Tiles of one render merge into exactly the image a single
//! process renders, since every pixel's samples are the same.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::job::{state_path, write_image};
use crate::error::{Error, Result};
use crate::film::{Film, Region};
use crate::io::state::{StateFile, StateHeader};

/// Merges `parts` into `output`; returns a one-line summary.
pub fn merge(output: &Path, parts: &[PathBuf]) -> Result<String> {
    let mut pieces = Vec::with_capacity(parts.len());
    for part in parts {
        let state = state_path(part);
        // Anything else there (a FIFO, a device) is refused by opening it.
        if !state.exists() {
            return Err(Error::Input(format!(
                "{}: no film state {} beside it (render pieces with --tile or --crop)",
                part.display(),
                state.display()
            )));
        }
        // Refused by its header before its pixels are read.
        let file = StateFile::open(&state)?;
        let header = file.header.clone();
        if !header.complete() {
            return Err(Error::Input(format!(
                "{}: incomplete: its film state {} holds {} of {} samples per pixel \
                 (finish it with --resume)",
                part.display(),
                state.display(),
                header.samples_done,
                header.target
            )));
        }
        pieces.push((part, header, file.read_film()?));
    }
    let (first, head, _) = &pieces[0];
    for (part, h, _) in &pieces[1..] {
        let clash = if (h.width, h.height) != (head.width, head.height) {
            Some(format!("an image size of {}x{}", h.width, h.height))
        } else if h.scene_hash != head.scene_hash {
            Some("another scene (its scene hash differs)".into())
        } else if h.frame != head.frame {
            Some(format!("frame {}", h.frame))
        } else if h.backend != head.backend {
            // Backends agree only to rounding: the result would be no
            // backend's image.
            Some(format!("backend {}", h.backend))
        } else {
            None
        };
        if let Some(what) = clash {
            return Err(Error::Input(format!(
                "{} has {what}, unlike {}",
                part.display(),
                first.display()
            )));
        }
    }

    // Pieces of one region add up; different regions must tile the image.
    let mut groups: BTreeMap<(usize, usize, usize, usize), Vec<usize>> = BTreeMap::new();
    for (i, (_, h, _)) in pieces.iter().enumerate() {
        let r = h.region;
        groups.entry((r.y0, r.x0, r.y1, r.x1)).or_default().push(i);
    }
    let name = |i: usize| pieces[i].0.display().to_string();
    let regions: Vec<(Region, &Vec<usize>)> = groups
        .values()
        .map(|members| (pieces[members[0]].1.region, members))
        .collect();
    for (a, (ra, ma)) in regions.iter().enumerate() {
        for (rb, mb) in &regions[a + 1..] {
            if ra.x0 < rb.x1 && rb.x0 < ra.x1 && ra.y0 < rb.y1 && rb.y0 < ra.y1 {
                return Err(Error::Input(format!(
                    "{} and {} overlap but are not the same region",
                    name(ma[0]),
                    name(mb[0])
                )));
            }
        }
        for (k, &i) in ma.iter().enumerate() {
            if let Some(&j) = ma[..k]
                .iter()
                .find(|&&j| pieces[j].1.seed == pieces[i].1.seed)
            {
                return Err(Error::Input(format!(
                    "{} and {} are the same region with the same seed: the same samples twice \\
                     (render extra samples with another seed)",
                    name(j),
                    name(i)
                )));
            }
        }
    }
    let covered: usize = regions.iter().map(|(r, _)| r.area()).sum();
    if covered != head.width * head.height {
        return Err(Error::Input(format!(
            "the parts cover {covered} of the {}x{} image's {} pixels: {}",
            head.width,
            head.height,
            head.width * head.height,
            gaps(
                &regions.iter().map(|(r, _)| *r).collect::<Vec<_>>(),
                head.height
            )
        )));
    }

    // Parts of a region add their samples: no more than a u32 counts. A
    // part's spp, samples_done and pixel counts are at most its target, so
    // their sums fit too.
    for (_, members) in &regions {
        members
            .iter()
            .try_fold(0u32, |sum, &i| sum.checked_add(pieces[i].1.target))
            .ok_or_else(|| {
                Error::Input(format!(
                    "the parts of the region of {} add up to more than {} samples per pixel",
                    name(members[0]),
                    u32::MAX
                ))
            })?;
    }
    let mut whole = Film::new(head.width, head.height);
    for (region, members) in &regions {
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let pixel = whole.pixel_mut(x, y);
                for &i in members.iter() {
                    pixel.merge(pieces[i].2.pixel(x, y));
                }
            }
        }
    }
    // The header of the first region's pieces: spp adds up within a region.
    let (_, members) = &regions[0];
    let total = |field: fn(&StateHeader) -> u32| members.iter().map(|&i| field(&pieces[i].1)).sum();
    let (spp, samples_done, target) = (
        total(|h| h.spp),
        total(|h| h.samples_done),
        total(|h| h.target),
    );
    let header = StateHeader {
        region: Region::whole(head.width, head.height),
        spp,
        target,
        samples_done,
        ..pieces[members[0]].1.clone()
    };
    write_image(output, &whole, &header)?;
    Ok(format!(
        "{} parts in {} regions, {}x{}, {spp} spp",
        pieces.len(),
        regions.len(),
        head.width,
        head.height
    ))
}

/// The first rows no part covers, for the error message.
fn gaps(regions: &[Region], height: usize) -> String {
    let missing: Vec<usize> = (0..height)
        .filter(|&y| !regions.iter().any(|r| (r.y0..r.y1).contains(&y)))
        .collect();
    match missing.first() {
        Some(&y) => format!(
            "rows from {y} on are missing ({} rows in all)",
            missing.len()
        ),
        None => "some columns are missing".into(),
    }
}
