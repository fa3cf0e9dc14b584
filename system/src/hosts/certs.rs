//! The private CA of a run's hosts and their certificates
//! (`learnpnp-supervisor link-certs`): one CA per cluster, a certificate for
//! host A (the bridge that listens, named by the addresses host B connects
//! to), one for host B (the host of remote agents) and one per read-only
//! monitor. Each host gets a directory of its own holding the CA's
//! certificate, its certificate and its private key, the one thing copied to
//! that host ([`HostFiles`](crate::hosts::certs::HostFiles)); the CA's key stays in `ca/` with whoever makes
//! certificates. Made with `rcgen`; every private key is written readable by
//! its owner only.
//!
//! Host A's access control names its peers by the common names here
//! ([`HOST_B_NAME`](crate::hosts::certs::HOST_B_NAME), [`MONITOR_NAME`](crate::hosts::certs::MONITOR_NAME)); a certificate's common name is what
//! the link authenticates, never a Zenoh id or an address.

use std::io::Write as _;
use std::net::IpAddr;
use std::path::{Path, PathBuf};

use rcgen::{
    BasicConstraints, CertificateParams, DistinguishedName, DnType, ExtendedKeyUsagePurpose, IsCa, Issuer, KeyPair,
    KeyUsagePurpose, SanType,
};

/// The common name of host A's certificate.
pub(crate) const HOST_A_NAME: &str = "learnpnp-host-a";

/// The common name of host B's certificate (the host of remote agents).
pub const HOST_B_NAME: &str = "learnpnp-host-b";

/// The common name of every read-only monitor's certificate.
pub const MONITOR_NAME: &str = "learnpnp-monitor";

/// The CA's certificate, in every host's directory and in `ca/`.
pub(crate) const CA_CERT: &str = "ca.pem";

/// The CA's private key, in `ca/` only.
pub(crate) const CA_KEY: &str = "ca-key.pem";

/// A host's certificate, in its directory.
pub(crate) const CERT: &str = "cert.pem";

/// A host's private key, in its directory.
pub(crate) const KEY: &str = "key.pem";

/// The directory of the CA, under the certificates' root.
pub const CA_DIR: &str = "ca";

/// Host A's directory, under the certificates' root.
pub const HOST_A_DIR: &str = "host-a";

/// Host B's directory, under the certificates' root.
pub const HOST_B_DIR: &str = "host-b";

/// How long a host's certificate is valid, in days.
pub(crate) const HOST_VALID_DAYS: i64 = 365;

/// How long the CA is valid, in days.
pub(crate) const CA_VALID_DAYS: i64 = 10 * 365;

/// Why certificates cannot be made or read.
#[derive(Debug, thiserror::Error)]
pub enum CertError {
    /// A file cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// rcgen refused.
    #[error("{what}: {source}")]
    Rcgen {
        /// What was being made.
        what: String,
        /// The error.
        source: rcgen::Error,
    },
    /// A host's directory lacks a file.
    #[error("{dir}: no {file} (make the directory with `learnpnp-supervisor link-certs`)")]
    Missing {
        /// The directory.
        dir: PathBuf,
        /// The file it lacks.
        file: &'static str,
    },
    /// Host A's certificate needs a name or address to be verified by.
    #[error("host A's certificate needs at least one address or DNS name host B connects to (--host-a)")]
    NoHostAName,
}

fn rcgen_error(what: impl Into<String>) -> impl FnOnce(rcgen::Error) -> CertError {
    let what = what.into();
    move |source| CertError::Rcgen { what, source }
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> CertError + '_ {
    move |source| CertError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The three files a host needs: the CA's certificate, its own, its key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostFiles {
    /// The CA's certificate (the only root the link trusts).
    pub ca: PathBuf,
    /// This host's certificate.
    pub cert: PathBuf,
    /// This host's private key.
    pub key: PathBuf,
}

impl HostFiles {
    /// The files of the host directory `dir`, checked to exist.
    pub fn in_dir(dir: &Path) -> Result<Self, CertError> {
        let files = HostFiles {
            ca: dir.join(CA_CERT),
            cert: dir.join(CERT),
            key: dir.join(KEY),
        };
        for (path, file) in [(&files.ca, CA_CERT), (&files.cert, CERT), (&files.key, KEY)] {
            if !path.is_file() {
                return Err(CertError::Missing {
                    dir: dir.to_path_buf(),
                    file,
                });
            }
        }
        Ok(files)
    }
}

/// What to make: host A's names, the monitors.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CertRequest {
    /// The addresses or DNS names host B connects to host A by (its
    /// certificate's subject alternative names; the link verifies them).
    pub host_a: Vec<String>,
    /// The monitors' directory names (each gets a certificate named
    /// [`MONITOR_NAME`]).
    pub monitors: Vec<String>,
}

/// What [`make`] wrote.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Made {
    /// A CA was made (false: the one in `ca/` was used).
    pub new_ca: bool,
    /// The host directories written.
    pub dirs: Vec<PathBuf>,
}

/// Writes `bytes` to `path`, readable by its owner only when `private`.
fn write(path: &Path, bytes: &[u8], private: bool) -> Result<(), CertError> {
    use std::os::unix::fs::OpenOptionsExt as _;
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create(true).truncate(true);
    if private {
        options.mode(0o600);
    }
    let mut file = options.open(path).map_err(io_error(path))?;
    file.write_all(bytes).map_err(io_error(path))
}

fn params(common_name: &str, days: i64) -> CertificateParams {
    let mut params = CertificateParams::default();
    let mut dn = DistinguishedName::new();
    dn.push(DnType::CommonName, common_name);
    dn.push(DnType::OrganizationName, "learnpnp run");
    params.distinguished_name = dn;
    let now = time::OffsetDateTime::now_utc();
    params.not_before = now - time::Duration::hours(1);
    params.not_after = now + time::Duration::days(days);
    params
}

/// A certificate of the CA `issuer` for `common_name`, with `names` as its
/// subject alternative names (addresses or DNS names), written with its key
/// and the CA's certificate into `dir`.
fn issue(
    dir: &Path,
    common_name: &str,
    names: &[String],
    server: bool,
    issuer: &Issuer<'_, KeyPair>,
    ca_pem: &str,
) -> Result<(), CertError> {
    std::fs::create_dir_all(dir).map_err(io_error(dir))?;
    let mut params = params(common_name, HOST_VALID_DAYS);
    params.subject_alt_names = names
        .iter()
        .map(|n| match n.parse::<IpAddr>() {
            Ok(ip) => Ok(SanType::IpAddress(ip)),
            Err(_) => n
                .as_str()
                .try_into()
                .map(SanType::DnsName)
                .map_err(rcgen_error(format!("the name '{n}'"))),
        })
        .collect::<Result<_, _>>()?;
    params.key_usages = vec![KeyUsagePurpose::DigitalSignature, KeyUsagePurpose::KeyEncipherment];
    params.extended_key_usages = if server {
        vec![ExtendedKeyUsagePurpose::ServerAuth, ExtendedKeyUsagePurpose::ClientAuth]
    } else {
        vec![ExtendedKeyUsagePurpose::ClientAuth]
    };
    let key = KeyPair::generate().map_err(rcgen_error("a key"))?;
    let cert = params
        .signed_by(&key, issuer)
        .map_err(rcgen_error(format!("the certificate of {common_name}")))?;
    write(&dir.join(KEY), key.serialize_pem().as_bytes(), true)?;
    write(&dir.join(CERT), cert.pem().as_bytes(), false)?;
    write(&dir.join(CA_CERT), ca_pem.as_bytes(), false)
}

/// The CA in `root/ca`, made there if it is not: its certificate (PEM) and issuer.
fn ca(root: &Path) -> Result<(String, Issuer<'static, KeyPair>, bool), CertError> {
    let dir = root.join(CA_DIR);
    let (cert_path, key_path) = (dir.join(CA_CERT), dir.join(CA_KEY));
    if cert_path.is_file() && key_path.is_file() {
        let pem = std::fs::read_to_string(&cert_path).map_err(io_error(&cert_path))?;
        let key_pem = std::fs::read_to_string(&key_path).map_err(io_error(&key_path))?;
        let key = KeyPair::from_pem(&key_pem).map_err(rcgen_error(key_path.display().to_string()))?;
        let issuer = Issuer::from_ca_cert_pem(&pem, key).map_err(rcgen_error(cert_path.display().to_string()))?;
        return Ok((pem, issuer, false));
    }
    std::fs::create_dir_all(&dir).map_err(io_error(&dir))?;
    let mut params = params("learnpnp private CA", CA_VALID_DAYS);
    params.is_ca = IsCa::Ca(BasicConstraints::Constrained(0));
    params.key_usages = vec![KeyUsagePurpose::KeyCertSign, KeyUsagePurpose::CrlSign];
    let key = KeyPair::generate().map_err(rcgen_error("the CA's key"))?;
    let cert = params.self_signed(&key).map_err(rcgen_error("the CA's certificate"))?;
    write(&key_path, key.serialize_pem().as_bytes(), true)?;
    write(&cert_path, cert.pem().as_bytes(), false)?;
    Ok((cert.pem(), Issuer::new(params, key), true))
}

/// Makes, under `root`, the CA (or uses the one already in `root/ca`) and
/// the directories of host A, host B and each monitor of `request`
/// (replacing certificates already there).
pub fn make(root: &Path, request: &CertRequest) -> Result<Made, CertError> {
    if request.host_a.is_empty() {
        return Err(CertError::NoHostAName);
    }
    let (ca_pem, issuer, new_ca) = ca(root)?;
    let mut made = Made {
        new_ca,
        dirs: Vec::new(),
    };
    let host_a = root.join(HOST_A_DIR);
    issue(&host_a, HOST_A_NAME, &request.host_a, true, &issuer, &ca_pem)?;
    made.dirs.push(host_a);
    let host_b = root.join(HOST_B_DIR);
    issue(&host_b, HOST_B_NAME, &[], false, &issuer, &ca_pem)?;
    made.dirs.push(host_b);
    for monitor in &request.monitors {
        let dir = root.join(monitor);
        issue(&dir, MONITOR_NAME, &[], false, &issuer, &ca_pem)?;
        made.dirs.push(dir);
    }
    Ok(made)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_call_keeps_the_ca_and_keys_are_private() {
        use std::os::unix::fs::PermissionsExt as _;
        let root = std::env::temp_dir().join(format!("learnpnp-certs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let request = CertRequest {
            host_a: vec!["198.18.7.1".into(), "host-a.example".into()],
            monitors: vec!["monitor".into()],
        };
        let first = make(&root, &request).unwrap();
        assert!(first.new_ca);
        let ca = std::fs::read(root.join(CA_DIR).join(CA_CERT)).unwrap();
        let second = make(&root, &request).unwrap();
        assert!(!second.new_ca);
        for dir in &second.dirs {
            let files = HostFiles::in_dir(dir).unwrap();
            assert_eq!(std::fs::read(&files.ca).unwrap(), ca, "{}", dir.display());
            let mode = std::fs::metadata(&files.key).unwrap().permissions().mode();
            assert_eq!(mode & 0o077, 0, "{}: the key is private", files.key.display());
        }
        assert!(matches!(
            HostFiles::in_dir(&root.join(CA_DIR)),
            Err(CertError::Missing { file: CERT, .. })
        ));
        assert!(matches!(
            make(&root, &CertRequest::default()),
            Err(CertError::NoHostAName)
        ));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
