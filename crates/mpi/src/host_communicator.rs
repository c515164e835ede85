//! A communicator the host application made and keeps -- a C or C++ code's `MPI_Comm`, an
//! mpi4py `Comm` -- taken by its Fortran handle (`MPI_Fint`, a C `int`: `MPI_Comm_c2f(comm)`
//! in C, `comm.py2f()` in mpi4py), so that neither the C header nor the Python extension
//! needs MPI's headers or mpi4py to be built. It is borrowed: never freed here, and MPI is
//! never initialised or finalised here (the host owns both).

use std::ffi::c_int;
use std::mem::ManuallyDrop;

use mpi::ffi;
use mpi::topology::SimpleCommunicator;
use mpi::traits::FromRaw;

use crate::error::{Error, Result};

/// The host's communicator for the length of a call (see the module's documentation).
pub struct HostCommunicator {
    /// rsmpi frees a user communicator when its `SimpleCommunicator` drops: never drop it.
    communicator: ManuallyDrop<SimpleCommunicator>,
}

impl HostCommunicator {
    /// The communicator whose Fortran handle is `handle`. Refused, naming why: MPI not
    /// initialised or already finalised, `MPI_COMM_NULL`, or an inter-communicator (the
    /// processes must form one group).
    ///
    /// # Safety
    /// `handle` is `MPI_COMM_NULL`'s handle or that of a live communicator of this process
    /// (not freed while the value is used). Open MPI maps an integer that names no
    /// communicator to `MPI_COMM_NULL`; other MPI implementations may not.
    pub unsafe fn from_fortran(handle: c_int) -> Result<Self> {
        let refused = |why: String| Err(Error::Communicator(format!("handle {handle}: {why}")));
        if !mpi::is_initialized() {
            return refused(
                "MPI is not initialised (the application initialises it -- MPI_Init, or \
                 importing mpi4py.MPI -- before rendering)"
                    .into(),
            );
        }
        if mpi::is_finalized() {
            return refused("MPI is finalised already".into());
        }
        // SAFETY: MPI is initialised and not finalised; the conversion takes any integer.
        let raw = unsafe { ffi::MPI_Comm_f2c(handle) };
        // SAFETY: reading constants rsmpi's shim sets at load time.
        let (null, world, own) = unsafe {
            (
                ffi::RSMPI_COMM_NULL,
                ffi::RSMPI_COMM_WORLD,
                ffi::RSMPI_COMM_SELF,
            )
        };
        if raw == null {
            return refused("MPI_COMM_NULL, or no communicator of this process".into());
        }
        let mut inter: c_int = 0;
        // SAFETY: `raw` is a live communicator (caller contract); `inter` is writable.
        unsafe { ffi::MPI_Comm_test_inter(raw, &mut inter) };
        if inter != 0 {
            return refused("an inter-communicator: the processes must form one group".into());
        }
        let communicator = if raw == world {
            SimpleCommunicator::world()
        } else if raw == own {
            SimpleCommunicator::self_comm()
        } else {
            // SAFETY: a live intra-communicator (caller contract, checked above) that is
            // neither MPI_COMM_WORLD nor MPI_COMM_SELF, as `from_raw` requires. It would free
            // the handle when dropped, which the `ManuallyDrop` around it prevents: the host
            // keeps and frees its own communicator.
            unsafe { SimpleCommunicator::from_raw(raw) }
        };
        Ok(Self {
            communicator: ManuallyDrop::new(communicator),
        })
    }

    /// The communicator, to pass to [`render_composited`](crate::render_composited).
    pub fn communicator(&self) -> &SimpleCommunicator {
        &self.communicator
    }
}
