//! `render --tev`: a test server speaking tev's TCP protocol (as tev's Ipc.cpp reads
//! it: little-endian packets, each a u32 length that counts itself, a type byte and
//! its fields) receives the image a render streams, and what it assembles is the EXR
//! the render writes. Without a tev listening the render goes on with one warning.

mod common;

use std::io::Read;
use std::net::TcpListener;
use std::path::Path;
use std::process::Command;

use common::{repo, temp_dir};

/// One packet as tev reads it.
#[derive(Debug)]
enum Packet {
    Create {
        name: String,
        width: u32,
        height: u32,
        channels: Vec<String>,
    },
    Update {
        name: String,
        channels: Vec<String>,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        offsets: Vec<u64>,
        strides: Vec<u64>,
        data: Vec<f32>,
    },
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        let s = &self.bytes[self.at..self.at + n];
        self.at += n;
        s
    }
    fn u8(&mut self) -> u8 {
        self.take(1)[0]
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.take(8).try_into().unwrap())
    }
    fn string(&mut self) -> String {
        let end = self.bytes[self.at..]
            .iter()
            .position(|&b| b == 0)
            .expect("NUL-terminated string");
        let s = String::from_utf8(self.bytes[self.at..self.at + end].to_vec()).expect("utf-8");
        self.at += end + 1;
        s
    }
}

fn decode(body: &[u8]) -> Packet {
    let mut r = Reader { bytes: body, at: 0 };
    match r.u8() {
        // CreateImage
        4 => {
            let _grab_focus = r.u8();
            let name = r.string();
            let (width, height) = (r.u32(), r.u32());
            let n = r.u32();
            let channels = (0..n).map(|_| r.string()).collect();
            assert_eq!(r.at, body.len(), "trailing bytes in a create packet");
            Packet::Create {
                name,
                width,
                height,
                channels,
            }
        }
        // UpdateImageV3
        6 => {
            let _grab_focus = r.u8();
            let name = r.string();
            let n = r.u32() as usize;
            let channels = (0..n).map(|_| r.string()).collect();
            let (x, y, width, height) = (r.u32(), r.u32(), r.u32(), r.u32());
            let offsets = (0..n).map(|_| r.u64()).collect();
            let strides = (0..n).map(|_| r.u64()).collect();
            let rest = &body[r.at..];
            assert_eq!(rest.len() % 4, 0, "pixel data of whole floats");
            let data = rest
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                .collect();
            Packet::Update {
                name,
                channels,
                x,
                y,
                width,
                height,
                offsets,
                strides,
                data,
            }
        }
        t => panic!("unexpected packet type {t}"),
    }
}

/// Accepts one connection and reads packets until it closes.
fn serve(listener: TcpListener) -> Vec<Packet> {
    let (mut socket, _) = listener.accept().expect("accept");
    let mut all = Vec::new();
    socket.read_to_end(&mut all).expect("read");
    let mut packets = Vec::new();
    let mut at = 0;
    while at < all.len() {
        let len = u32::from_le_bytes(all[at..at + 4].try_into().unwrap()) as usize;
        assert!(len >= 5 && at + len <= all.len(), "packet length {len}");
        packets.push(decode(&all[at + 4..at + len]));
        at += len;
    }
    packets
}

fn render(args: &[&str], out: &Path) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_wavetrace"))
        .current_dir(repo(""))
        .args(["render", "scenes/cbox/cbox_path.xml", "-D", "res=24", "-q"])
        .args(args)
        .arg("-o")
        .arg(out)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run wavetrace");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn tev_receives_the_image_the_render_writes() {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let address = listener.local_addr().expect("address").to_string();
    let server = std::thread::spawn(move || serve(listener));
    let out = temp_dir("stream").join("streamed.exr");
    // Small batches: several steps, so the render goes through the streaming loop.
    let (ok, err) = render(&["--spp", "8", "--batch", "1000", "--tev", &address], &out);
    assert!(ok, "render failed: {err}");
    assert!(err.contains("streaming to tev"), "{err}");
    let packets = server.join().expect("server thread");

    let Some(Packet::Create {
        name,
        width,
        height,
        channels,
    }) = packets.first()
    else {
        panic!("the first packet is not a create: {packets:?}");
    };
    assert_eq!(name, "streamed.exr");
    assert_eq!((*width, *height), (24, 24));
    assert_eq!(channels, &["R", "G", "B"]);
    let (w, h) = (*width as usize, *height as usize);
    let mut image = vec![f32::NAN; w * h * 3];
    let mut updates = 0;
    for p in &packets[1..] {
        let Packet::Update {
            name: n,
            channels: c,
            x,
            y,
            width: uw,
            height: uh,
            offsets,
            strides,
            data,
        } = p
        else {
            panic!("a second create packet");
        };
        assert_eq!((n, c), (name, channels));
        updates += 1;
        for j in 0..*uh as usize {
            for i in 0..*uw as usize {
                let pixel = (*y as usize + j) * w + *x as usize + i;
                for ch in 0..3 {
                    let k = offsets[ch] as usize + (j * *uw as usize + i) * strides[ch] as usize;
                    image[pixel * 3 + ch] = data[k];
                }
            }
        }
    }
    assert!(updates >= 1, "no update packets");
    // The EXR holds half floats (the scene's component format, Mitsuba's default):
    // tev got the floats they were rounded from.
    let exr = wavetrace::image::Image::read_exr(&out).expect("read the EXR");
    for (i, (a, b)) in image.iter().zip(&exr.rgb).enumerate() {
        assert!(
            (a - b).abs() <= 1e-3 * b.abs() + 1e-6,
            "value {i}: tev got {a}, the EXR holds {b}"
        );
    }
}

#[test]
fn without_tev_the_render_goes_on_with_one_warning() {
    // A port nobody listens on: bind one, then free it.
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("free port")
        .port();
    let out = temp_dir("absent").join("absent.exr");
    let (ok, err) = render(&["--spp", "2", "--tev", &format!("127.0.0.1:{port}")], &out);
    assert!(ok, "render failed: {err}");
    assert_eq!(err.matches("warning").count(), 1, "{err}");
    assert!(err.contains("tev"), "{err}");
    assert!(out.exists(), "no EXR written");
}
