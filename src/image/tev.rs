//! Streaming an image in progress to tev (Tom94/tev), the HDR image viewer, over its
//! TCP protocol (packets encoded by the `tev_client` crate): one "create image"
//! packet with the size and channel names, then "update image" packets of float
//! pixels, a band of rows each, whenever the caller has a newer image.
//!
//! tev listens on 127.0.0.1:14158 by default ([`DEFAULT_ADDRESS`]).

use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

use tev_client::{PacketCreateImage, PacketUpdateImage, TevClient};

use super::Error;

/// Where tev listens unless told otherwise.
pub const DEFAULT_ADDRESS: &str = "127.0.0.1:14158";
/// How long to wait for tev to accept the connection.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(2);
/// Most floats in one update packet (4 MiB): larger images go as several bands.
const PACKET_FLOATS: usize = 1 << 20;

/// An image open in tev.
pub struct TevStream {
    /// `None` once closed ([`TevStream::close`]).
    client: Option<TevClient>,
    address: String,
    name: String,
    width: u32,
    height: u32,
    channels: Vec<String>,
}

impl TevStream {
    /// Connects to tev at `address` (HOST:PORT) and creates the image `name` of
    /// `width` x `height` pixels with `channels` (e.g. R, G, B), replacing one of that
    /// name.
    pub fn create(
        address: &str,
        name: &str,
        width: u32,
        height: u32,
        channels: &[&str],
    ) -> Result<TevStream, Error> {
        let io_error = |message: String| Error::Tev {
            address: address.to_string(),
            message,
        };
        if width == 0 || height == 0 || channels.is_empty() {
            return Err(io_error(format!(
                "cannot show an image of {width}x{height} pixels and {} channels",
                channels.len()
            )));
        }
        if name.contains('\0') || channels.iter().any(|c| c.contains('\0')) {
            return Err(io_error("names must not contain NUL characters".into()));
        }
        let addrs: Vec<_> = address
            .to_socket_addrs()
            .map_err(|e| io_error(format!("not an address ({e})")))?
            .collect();
        let mut last = None;
        let mut socket = None;
        for a in &addrs {
            match TcpStream::connect_timeout(a, CONNECT_TIMEOUT) {
                Ok(s) => {
                    socket = Some(s);
                    break;
                }
                Err(e) => last = Some(e),
            }
        }
        let socket = socket.ok_or_else(|| {
            io_error(match last {
                Some(e) => format!("cannot connect ({e}); is tev running?"),
                None => "the address resolves to nothing".into(),
            })
        })?;
        let _ = socket.set_nodelay(true);
        let mut stream = TevStream {
            client: Some(TevClient::wrap(socket)),
            address: address.to_string(),
            name: name.to_string(),
            width,
            height,
            channels: channels.iter().map(|c| c.to_string()).collect(),
        };
        let packet = PacketCreateImage {
            image_name: &stream.name,
            grab_focus: true,
            width,
            height,
            channel_names: &stream.channels,
        };
        send(&mut stream.client, packet)
            .map_err(|e| io_error(format!("sending the image failed ({e})")))?;
        Ok(stream)
    }

    /// Sends the whole image: `data` holds every pixel's channels interleaved, top
    /// row first, in the order given to [`TevStream::create`].
    pub fn update(&mut self, data: &[f32]) -> Result<(), Error> {
        let n = self.channels.len();
        let row = self.width as usize * n;
        if data.len() != row * self.height as usize {
            return Err(Error::Tev {
                address: self.address.clone(),
                message: format!(
                    "an update of {} values for a {}x{} image of {n} channels",
                    data.len(),
                    self.width,
                    self.height
                ),
            });
        }
        let rows_per_packet = (PACKET_FLOATS / row).max(1);
        let offsets: Vec<u64> = (0..n as u64).collect();
        let strides = vec![n as u64; n];
        for (band, chunk) in data.chunks(rows_per_packet * row).enumerate() {
            let packet = PacketUpdateImage {
                image_name: &self.name,
                grab_focus: false,
                channel_names: &self.channels,
                channel_offsets: &offsets,
                channel_strides: &strides,
                x: 0,
                y: (band * rows_per_packet) as u32,
                width: self.width,
                height: (chunk.len() / row) as u32,
                data: chunk,
            };
            send(&mut self.client, packet).map_err(|e| Error::Tev {
                address: self.address.clone(),
                message: format!("sending pixels failed ({e})"),
            })?;
        }
        Ok(())
    }

    /// Drops the connection: later updates fail.
    pub fn close(&mut self) {
        self.client = None;
    }

    pub fn is_closed(&self) -> bool {
        self.client.is_none()
    }
}

/// Sends one packet on the connection, if it is open.
fn send(client: &mut Option<TevClient>, packet: impl tev_client::TevPacket) -> std::io::Result<()> {
    match client.as_mut() {
        Some(c) => c.send(packet),
        None => Err(std::io::Error::new(
            std::io::ErrorKind::NotConnected,
            "the connection to tev is closed",
        )),
    }
}
