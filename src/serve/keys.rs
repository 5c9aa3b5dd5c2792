//! The server's secrets and who may log in: the host key (generated on first start, stored
//! with mode 0600, refused when others can read it), the authorized public keys (OpenSSH's
//! `authorized_keys` format), and the class password (the first line of a file, compared in
//! constant time, never logged).

use std::io::Write;
use std::os::unix::fs::{DirBuilderExt, OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};

use russh::keys::ssh_key::private::Ed25519Keypair;
use russh::keys::ssh_key::{AuthorizedKeys, LineEnding};
use russh::keys::{HashAlg, PrivateKey, PublicKey};

use super::ServeError;

/// A key or password file's problem, in words.
fn secret(text: String) -> ServeError {
    ServeError::Secret(text)
}

/// The host key at `path`, created (with its directory) when there is none. Returns the key
/// and whether it was created now.
pub fn load_or_create_host_key(path: &Path) -> Result<(PrivateKey, bool), ServeError> {
    let shown = path.display();
    if path.exists() {
        refuse_if_others_can_read(path, "host key")?;
        let text = std::fs::read_to_string(path)
            .map_err(|e| secret(format!("cannot read the host key {shown}: {e}")))?;
        let key = PrivateKey::from_openssh(&text).map_err(|e| not_a_key(path, &text, &e))?;
        if key.is_encrypted() {
            // It would load, and then no client could log in: every handshake fails.
            return Err(secret(format!(
                "the host key {shown} is encrypted with a passphrase, which the server cannot \
                 ask for; {}",
                how_to_make_one(path)
            )));
        }
        return Ok((key, false));
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(parent)
            .map_err(|e| secret(format!("cannot create {}: {e}", parent.display())))?;
    }
    let mut seed = [0u8; 32];
    std::fs::File::open("/dev/urandom")
        .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut seed))
        .map_err(|e| secret(format!("cannot read /dev/urandom for a host key: {e}")))?;
    let key = PrivateKey::from(Ed25519Keypair::from_seed(&seed));
    let text = key
        .to_openssh(LineEnding::LF)
        .map_err(|e| secret(format!("cannot encode the host key: {e}")))?;
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)
        .map_err(|e| secret(format!("cannot create the host key {shown}: {e}")))?;
    file.write_all(text.as_bytes())
        .and_then(|()| file.sync_all())
        .map_err(|e| secret(format!("cannot write the host key {shown}: {e}")))?;
    Ok((key, true))
}

/// Why `text` (read from `path`) is not a host key, in words a lecturer can act on.
fn not_a_key(path: &Path, text: &str, error: &dyn std::fmt::Display) -> ServeError {
    let shown = path.display();
    let why = if text.trim().is_empty() {
        "it is empty".to_string()
    } else if !text
        .trim_start()
        .starts_with("-----BEGIN OPENSSH PRIVATE KEY-----")
    {
        "it does not begin with -----BEGIN OPENSSH PRIVATE KEY----- (a key in another format, \
         such as PEM's BEGIN RSA PRIVATE KEY, is converted with ssh-keygen -p -f FILE)"
            .to_string()
    } else {
        format!("it cannot be decoded ({error})")
    };
    secret(format!(
        "the host key {shown} is not an OpenSSH private key: {why}; {}",
        how_to_make_one(path)
    ))
}

/// The advice closing every refused host key: where a usable one comes from.
fn how_to_make_one(path: &Path) -> String {
    format!(
        "move it away and the server makes a new one there, or make one with \
         ssh-keygen -t ed25519 -N '' -f {}",
        path.display()
    )
}

/// Where the host key lives unless `--host-key` says: under `$XDG_CONFIG_HOME/beamfric` (or
/// `~/.config/beamfric`), else in the current directory.
pub fn default_host_key_path() -> PathBuf {
    let config = std::env::var_os("XDG_CONFIG_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|home| PathBuf::from(home).join(".config")));
    match config {
        Some(dir) => dir.join("beamfric").join("ssh_host_ed25519_key"),
        None => PathBuf::from("beamfric_ssh_host_ed25519_key"),
    }
}

/// The SHA-256 fingerprint as OpenSSH prints it (`SHA256:…`).
pub fn fingerprint(key: &PublicKey) -> String {
    key.fingerprint(HashAlg::Sha256).to_string()
}

/// The public keys of an `authorized_keys` file (options such as `from=` are not supported
/// and refused, so that nothing is silently ignored).
pub fn read_authorized_keys(path: &Path) -> Result<Vec<PublicKey>, ServeError> {
    let shown = path.display();
    let entries = AuthorizedKeys::read_file(path)
        .map_err(|e| secret(format!("cannot read the authorized keys {shown}: {e}")))?;
    let mut keys = Vec::new();
    for entry in entries {
        if !entry.config_opts().is_empty() {
            return Err(secret(format!(
                "{shown}: options ({}) are not supported",
                entry.config_opts().as_str()
            )));
        }
        keys.push(entry.public_key().clone());
    }
    if keys.is_empty() {
        return Err(secret(format!("{shown} lists no key")));
    }
    Ok(keys)
}

/// The class password: the first line of the file, which others must not be able to read.
pub fn read_password(path: &Path) -> Result<String, ServeError> {
    refuse_if_others_can_read(path, "password file")?;
    let text = std::fs::read_to_string(path).map_err(|e| {
        secret(format!(
            "cannot read the password file {}: {e}",
            path.display()
        ))
    })?;
    let password = text.lines().next().unwrap_or("").to_string();
    if password.is_empty() {
        return Err(secret(format!(
            "{}: the first line is empty",
            path.display()
        )));
    }
    Ok(password)
}

/// Compares in time that depends only on the lengths, not on where the texts differ.
pub fn same_secret(given: &str, expected: &str) -> bool {
    let (a, b) = (given.as_bytes(), expected.as_bytes());
    let mut difference = a.len() ^ b.len();
    for (i, byte) in b.iter().enumerate() {
        difference |= usize::from(a.get(i).copied().unwrap_or(0) ^ byte);
    }
    difference == 0
}

fn refuse_if_others_can_read(path: &Path, what: &str) -> Result<(), ServeError> {
    let mode = std::fs::metadata(path)
        .map_err(|e| secret(format!("cannot read the {what} {}: {e}", path.display())))?
        .permissions()
        .mode();
    if mode & 0o077 != 0 {
        return Err(secret(format!(
            "the {what} {} can be read by others (mode {:o}): chmod 600 it",
            path.display(),
            mode & 0o777
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn secrets_compare_whole() {
        assert!(same_secret("tiger", "tiger"));
        assert!(!same_secret("tige", "tiger"));
        assert!(!same_secret("tigers", "tiger"));
        assert!(!same_secret("tigeR", "tiger"));
        assert!(!same_secret("", "tiger"));
    }

    #[test]
    fn a_host_key_is_created_private_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("keys").join("host");
        let (created, fresh) = load_or_create_host_key(&path).unwrap();
        assert!(fresh);
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600);
        let (loaded, fresh) = load_or_create_host_key(&path).unwrap();
        assert!(!fresh);
        assert_eq!(
            fingerprint(created.public_key()),
            fingerprint(loaded.public_key())
        );
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o644)).unwrap();
        let refused = load_or_create_host_key(&path).unwrap_err();
        assert!(matches!(refused, ServeError::Secret(_)), "{refused:?}");
        assert!(refused.to_string().contains("chmod 600"), "{refused}");
    }

    /// `ssh-keygen -t ed25519 -N pw`: a key that needs its passphrase.
    const ENCRYPTED: &str = "-----BEGIN OPENSSH PRIVATE KEY-----
b3BlbnNzaC1rZXktdjEAAAAACmFlczI1Ni1jdHIAAAAGYmNyeXB0AAAAGAAAABAUufQ9el
xvsDJ9fFaOB8edAAAAEAAAAAEAAAAzAAAAC3NzaC1lZDI1NTE5AAAAIBmCR/4YgkfoNJah
s4JZf8ow7/YabzCC21vdUJ8ksJUGAAAAkJw/m6OL7TCYqJuZOh34Ypq6C25fxzxsGbcA7I
muN3R+ajB+OIDhSfgbPgMZSKLOQN3IZCcs/xD7iNft7xC0W4YS6NlA4N+TqitoMQJrwZ5Y
ohS52b5/eseeNjHFALk5JPn9UJAYxb0az7NIeSs0OYe1LWnb9ynAAP/qW7Sb5c3Fy70Rhl
P3SY43VDrcnJfqWQ==
-----END OPENSSH PRIVATE KEY-----
";

    /// Writes `text` as a private host key file and returns what loading it says.
    fn refusal_of(text: &str) -> String {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("host");
        std::fs::write(&path, text).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).unwrap();
        let refused = load_or_create_host_key(&path).unwrap_err();
        assert!(matches!(refused, ServeError::Secret(_)), "{refused:?}");
        let message = refused.to_string();
        assert!(message.contains(&path.display().to_string()), "{message}");
        assert!(message.contains("ssh-keygen -t ed25519 -N ''"), "{message}");
        message
    }

    #[test]
    fn a_host_key_that_cannot_serve_is_refused_saying_why() {
        // Stop 58's hostile pass: an empty file was "PEM preamble contains invalid data (NUL
        // byte)"; a key with a passphrase loaded, and then every client's handshake failed.
        assert!(refusal_of("").contains("it is empty"));
        assert!(refusal_of("junk\0").contains("does not begin with -----BEGIN OPENSSH"));
        let pem = "-----BEGIN RSA PRIVATE KEY-----\nMIIB\n-----END RSA PRIVATE KEY-----\n";
        assert!(refusal_of(pem).contains("ssh-keygen -p -f FILE"));
        let cut = "-----BEGIN OPENSSH PRIVATE KEY-----\nabc\n-----END OPENSSH PRIVATE KEY-----\n";
        assert!(refusal_of(cut).contains("cannot be decoded"));
        assert!(refusal_of(ENCRYPTED).contains("encrypted with a passphrase"));
    }
}
