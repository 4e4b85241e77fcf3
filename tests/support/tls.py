"""Self-signed certificates made with ``cryptography``: for 127.0.0.1, what the HTTPS
tests of generated services and of their ROS clients serve and trust; for a DNS name
only (no address), what the callback tests serve, as a client verifies it only when it
checks the name, not the address it connected to."""

from __future__ import annotations

import datetime
import ipaddress
from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID


def self_signed(directory: Path) -> tuple[Path, Path]:
    """A certificate for the address 127.0.0.1, and its key: ``tls.crt``, ``tls.key``."""
    address = x509.IPAddress(ipaddress.ip_address("127.0.0.1"))
    return _written(directory, "127.0.0.1", address, "tls")


def certificate_for(name: str, directory: Path) -> tuple[Path, Path]:
    """A certificate for the DNS name ``name`` only, and its key."""
    return _written(directory, name, x509.DNSName(name), name)


def _written(
    directory: Path, common_name: str, alternative: x509.GeneralName, stem: str
) -> tuple[Path, Path]:
    key = ec.generate_private_key(ec.SECP256R1())
    subject = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, common_name)])
    now = datetime.datetime.now(datetime.UTC)
    certificate = (
        x509.CertificateBuilder()
        .subject_name(subject)
        .issuer_name(subject)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - datetime.timedelta(minutes=5))
        .not_valid_after(now + datetime.timedelta(days=1))
        .add_extension(x509.SubjectAlternativeName([alternative]), critical=False)
        .add_extension(x509.BasicConstraints(ca=True, path_length=None), critical=True)
        .sign(key, hashes.SHA256())
    )
    cert_file, key_file = directory / f"{stem}.crt", directory / f"{stem}.key"
    cert_file.write_bytes(certificate.public_bytes(serialization.Encoding.PEM))
    key_file.write_bytes(
        key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.PKCS8,
            serialization.NoEncryption(),
        )
    )
    return cert_file, key_file
