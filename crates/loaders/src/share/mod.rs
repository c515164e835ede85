//! One process's share of a scene file read by several ([`load_share`]), for drawing a scene
//! split between processes: each reads its own part of the file, and the shares together are
//! the scene one process loading the whole file gets ([`load()`](crate::load())), glyph for glyph
//! and bit for bit, each glyph with its index in that scene.
//!
//! How each format is divided ([`Split`]), how indices and species are numbered across the
//! processes and how a failing share is reported are specified once, in the repository's
//! `docs/mpi.md` ("The command-line tool under mpirun"). What holds it together here: every
//! step that can fail on one process is agreed on by all before any process waits on another
//! ([`Exchange`]); a process whose part holds a bad record reports it and the others return
//! [`Error::OtherRank`] naming it. The processes must see the same file (checked: its length
//! and head).

mod collective;
mod csv;
mod exchange;
mod ids;
mod line_ranges;
mod loaded_share;
mod particles;
mod ply;
mod species;

use std::path::Path;

pub use self::exchange::Exchange;
pub use self::loaded_share::{LoadedShare, Split};

use self::collective::Collective;
use self::line_ranges::TextFile;
use self::particles::Particles;
use crate::load::{detect_format, Format};
use crate::options::LoadOptions;
use crate::ply::VertexRecords;
use crate::{Error, Result};

/// How this process reads its share, decided from the file's head.
enum Plan {
    Csv(TextFile, csv::CsvHead),
    Particles(TextFile, particles::FrameHead, Particles),
    Ply(TextFile, VertexRecords),
    Whole,
}

impl Plan {
    /// What every process must find alike: the plan's kind, the file's length, where its
    /// records begin and how many the head promises.
    fn fingerprint(&self) -> Vec<u64> {
        match self {
            Plan::Csv(file, head) => vec![1, file.len(), head.data_start()],
            Plan::Particles(file, head, format) => {
                let (start, count) = head.atoms();
                vec![2 + *format as u64, file.len(), start, count as u64]
            }
            Plan::Ply(file, records) => {
                vec![4, file.len(), records.offset, records.count as u64]
            }
            Plan::Whole => vec![5],
        }
    }
}

/// Reads `path`'s head and decides how to read the rest.
fn plan(path: &Path, options: &LoadOptions) -> Result<Plan> {
    let format = detect_format(path)?;
    let particles = match format {
        Format::LammpsDump => Some(Particles::Lammps),
        Format::ExtendedXyz => Some(Particles::Xyz),
        _ => None,
    };
    let splits = matches!(format, Format::Csv | Format::GaussianPly) || particles.is_some();
    if !splits {
        return Ok(Plan::Whole);
    }
    let file = TextFile::open(path)?;
    // A gzip stream cannot be entered in the middle.
    if file.read(0, 2)? == [0x1f, 0x8b] && particles.is_some() {
        return Ok(Plan::Whole);
    }
    Ok(match (format, particles) {
        (_, Some(kind)) => match particles::read_head(&file, path, kind, options)? {
            Some(head) => Plan::Particles(file, head, kind),
            None => Plan::Whole,
        },
        (Format::Csv, _) => match csv::read_head(&file, path)? {
            Some(head) => Plan::Csv(file, head),
            None => Plan::Whole,
        },
        _ => match ply::read_records(&file, path)? {
            Some(records) => Plan::Ply(file, records),
            None => Plan::Whole,
        },
    })
}

/// This process's share of the scene file `path`, read with `options` together with the
/// other processes of `exchange` (every one of them calls this, with the same file and
/// options): see the [module documentation](self).
pub fn load_share(
    path: &Path,
    options: &LoadOptions,
    exchange: &dyn Exchange,
) -> Result<LoadedShare> {
    let c = Collective::new(exchange, path);
    let (plan, all) = c.agree(plan(path, options), Plan::fingerprint)?;
    if all.iter().any(|f| *f != all[0]) {
        let rank = all.iter().position(|f| *f != all[0]).unwrap_or(0);
        return Err(Error::invalid(
            "scene file",
            format!(
                "{}: rank {rank} sees a different file than rank 0 (its length or head \
                 differs): every process must read the same file",
                path.display()
            ),
        ));
    }
    match plan {
        Plan::Csv(file, head) => csv::load(&file, &head, path, options, c),
        Plan::Particles(file, head, format) => {
            particles::load(&file, &head, format, path, options, c)
        }
        Plan::Ply(file, records) => ply::load(&file, &records, path, options, c),
        Plan::Whole => {
            let (loaded, _) = c.agree(crate::load(path, options), |_| Vec::new())?;
            LoadedShare::of_whole(loaded, c.rank(), c.size())
        }
    }
}
