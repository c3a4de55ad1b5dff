//! A networked match: [`NetSession`] (`net_session.rs`) and how it starts
//! (`start.rs`: over UDP or in a signalling server's room).

mod net_session;
mod start;

pub use net_session::NetSession;
