//! SPIR-V of every kernel in `shaders/`, compiled by build.rs with glslang.

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

#[cfg(test)]
mod tests {
    use std::io::Write;
    use std::process::{Command, Stdio};

    /// `spirv-val`'s verdict on one module: `None` when valid, else its message.
    fn validate(spirv: &[u8]) -> Option<String> {
        let mut child = Command::new("spirv-val")
            .args(["--target-env", "vulkan1.2", "-"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spirv-val (Debian's spirv-tools, installed by tools/setup.sh) runs");
        child
            .stdin
            .take()
            .expect("piped stdin")
            .write_all(spirv)
            .expect("spirv-val reads the module");
        let out = child.wait_with_output().expect("spirv-val finishes");
        (!out.status.success()).then(|| {
            format!(
                "{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            )
        })
    }

    /// Every kernel glslang compiled is valid SPIR-V for Vulkan 1.2. glslang 11 once
    /// emitted invalid modules (a chain of `||` over specialization constants became a
    /// phi negated as a specialization constant): the driver then refused the pipeline
    /// only on the scenes that specialized that kernel, far from the cause. Here every
    /// module is checked, on two threads (about 30 s of CPU for ~100 modules).
    #[test]
    fn every_kernel_is_valid_spirv() {
        let halves: Vec<Vec<(&str, &[u8])>> = vec![
            super::ALL.iter().step_by(2).copied().collect(),
            super::ALL.iter().skip(1).step_by(2).copied().collect(),
        ];
        let invalid: Vec<String> = std::thread::scope(|s| {
            let handles: Vec<_> = halves
                .iter()
                .map(|half| {
                    s.spawn(move || {
                        half.iter()
                            .filter_map(|(name, spirv)| {
                                validate(spirv).map(|msg| format!("{name}: {msg}"))
                            })
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| h.join().expect("validation thread"))
                .collect()
        });
        assert!(super::ALL.len() > 50, "only {} kernels", super::ALL.len());
        assert!(
            invalid.is_empty(),
            "invalid SPIR-V:\n{}",
            invalid.join("\n")
        );
    }

    /// The check above can fail: a module whose header is cut short is refused.
    #[test]
    fn spirv_val_refuses_a_broken_module() {
        let (_, spirv) = super::ALL[0];
        assert!(validate(&spirv[..spirv.len() / 2]).is_some());
    }
}
