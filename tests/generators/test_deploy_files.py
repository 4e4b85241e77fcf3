"""Deployment files of the data-acquisition services: YAML that parses, with images,
ports, environment and secrets consistent between Dockerfile, compose and Kubernetes."""

from __future__ import annotations

import re

import pytest
import yaml

from spl.generators.deploy import generator as deploy
from spl.generators.service import generator as service

from support.service_models import product

EMBEDDED = ("DataAcquisition", "Embedded", "Follow", "Positions", "Storage")
POSTGRES = ("DataAcquisition", "Follow", "Positions", "Postgres", "Storage")
STORES = {"position-store": "POSITION_STORE_TOKEN", "follow-store": "FOLLOW_STORE_TOKEN"}


def documents(files: dict[str, bytes], path: str) -> list[dict]:
    return [d for d in yaml.safe_load_all(files[path]) if d is not None]


@pytest.fixture(scope="module", params=[EMBEDDED, POSTGRES], ids=["embedded", "postgres"])
def generated(request):  # type: ignore[no-untyped-def]
    resolved = product(features=request.param)
    return request.param is POSTGRES, deploy.generate(resolved), service.generate(resolved)


def test_compose_runs_every_service_with_its_token_from_the_environment(generated) -> None:
    postgres, files, services = generated
    compose = documents(files, "deploy/docker-compose.yml")[0]
    expected = set(STORES) | ({"postgres"} if postgres else set())
    assert set(compose["services"]) == expected
    host_ports = []
    for name, token_env in STORES.items():
        entry = compose["services"][name]
        store = {"position-store": "PositionStore", "follow-store": "FollowStore"}[name]
        assert entry["build"] == {"context": "..", "dockerfile": f"deploy/{store}/Dockerfile"}
        assert f"deploy/{store}/Dockerfile" in files
        assert entry["environment"][token_env] == f"${{{token_env}:?set {token_env}}}"
        url = entry["environment"]["DATABASE_URL"]
        if postgres:
            assert url.startswith("postgresql://spl:${POSTGRES_PASSWORD:?")
            assert entry["depends_on"]["postgres"]["condition"] == "service_healthy"
        else:
            assert url.startswith("sqlite:////data/")
            volume = entry["volumes"][0].split(":")[0]
            assert volume in compose["volumes"]
        host, container = entry["ports"][0].split(":")
        assert container == entry["environment"]["PORT"] == "8000"
        host_ports.append(host)
        dockerfile = files[f"deploy/{store}/Dockerfile"].decode()
        assert "EXPOSE 8000" in dockerfile and "PORT=8000" in dockerfile
        package = re.search(r'CMD \["python", "-m", "(\w+)"\]', dockerfile).group(1)
        assert f"services/{store}/{package}/__main__.py" in services
        assert f"COPY services/{store}/ /app/" in dockerfile
    assert len(set(host_ports)) == len(host_ports)
    if postgres:
        db = compose["services"]["postgres"]
        assert db["environment"]["POSTGRES_PASSWORD"].startswith("${POSTGRES_PASSWORD:?")
        assert "healthcheck" in db


def test_kubernetes_manifests_are_consistent(generated) -> None:
    postgres, files, _ = generated
    compose = documents(files, "deploy/docker-compose.yml")[0]
    for name, token_env in STORES.items():
        docs = {d["kind"]: d for d in documents(files, f"deploy/kubernetes/{name}.yaml")}
        assert {"Deployment", "Service", "NetworkPolicy"} <= set(docs)
        namespace = "data-acquisition"
        assert {d["metadata"]["namespace"] for d in docs.values()} == {namespace}
        deployment = docs["Deployment"]
        assert deployment["apiVersion"] == "apps/v1"
        labels = deployment["spec"]["selector"]["matchLabels"]
        assert deployment["spec"]["template"]["metadata"]["labels"].items() >= labels.items()
        assert docs["Service"]["spec"]["selector"] == labels
        container = deployment["spec"]["template"]["spec"]["containers"][0]
        assert container["image"] == compose["services"][name]["image"]
        assert container["ports"][0] == {"name": "https", "containerPort": 8000, "protocol": "TCP"}
        assert docs["Service"]["spec"]["ports"][0] == {
            "name": "https",
            "port": 443,
            "targetPort": "https",
            "protocol": "TCP",
        }
        pod = deployment["spec"]["template"]["spec"]
        assert pod["automountServiceAccountToken"] is False
        assert pod["securityContext"]["runAsNonRoot"] is True
        assert pod["securityContext"]["runAsUser"] >= 10000
        assert container["securityContext"]["readOnlyRootFilesystem"] is True
        assert container["securityContext"]["capabilities"] == {"drop": ["ALL"]}
        assert {"requests", "limits"} <= set(container["resources"])
        env = {e["name"]: e for e in container["env"]}
        # HTTPS from the TLS secret, mounted as files (read only), never a value here
        upper = name.replace("-", "_").upper()
        assert env[f"{upper}_TLS_CERT"]["value"] == "/etc/tls/tls.crt"
        assert env[f"{upper}_TLS_KEY"]["value"] == "/etc/tls/tls.key"
        assert {"name": "tls", "mountPath": "/etc/tls", "readOnly": True} in container[
            "volumeMounts"
        ]
        volumes = {v["name"]: v for v in deployment["spec"]["template"]["spec"]["volumes"]}
        assert volumes["tls"] == {
            "name": "tls",
            "secret": {"secretName": f"{name}-tls", "defaultMode": 0o440},
        }
        for probe in ("readinessProbe", "livenessProbe"):
            assert container[probe]["httpGet"]["scheme"] == "HTTPS"
        # ready: the root, a round trip to the database; alive: serving its OpenAPI document
        assert container["readinessProbe"]["httpGet"]["path"] == "/"
        assert container["livenessProbe"]["httpGet"]["path"] == "/openapi.json"
        assert env["PORT"]["value"] == "8000"
        # secrets as read-only files, each service mounting its own keys alone
        assert not any("valueFrom" in e for e in container["env"])
        assert env[f"{token_env}_FILE"]["value"] == "/run/secrets/spl/token"
        assert {"name": "secrets", "mountPath": "/run/secrets/spl", "readOnly": True} in (
            container["volumeMounts"]
        )
        secret = volumes["secrets"]["secret"]
        assert secret["secretName"] == "data-acquisition-secrets"
        keys = {item["key"]: item["path"] for item in secret["items"]}
        expected = {f"{name}-token": "token"}
        if postgres:
            expected["database-url"] = "database-url"
        assert keys == expected
        policy = docs["NetworkPolicy"]["spec"]
        assert policy["podSelector"] == {"matchLabels": labels}
        assert policy["egress"] == (
            [
                {
                    "to": [
                        {"podSelector": {"matchLabels": {"app.kubernetes.io/name": "postgres"}}}
                    ],
                    "ports": [{"protocol": "TCP", "port": 5432}],
                }
            ]
            if postgres
            else []
        )
        if postgres:
            assert env["DATABASE_URL_FILE"]["value"] == "/run/secrets/spl/database-url"
            assert "DATABASE_URL" not in env
        else:
            claim = volumes["data"]
            assert (
                docs["PersistentVolumeClaim"]["metadata"]["name"]
                == (claim["persistentVolumeClaim"]["claimName"])
            )
    if postgres:
        docs = {d["kind"]: d for d in documents(files, "deploy/kubernetes/postgres.yaml")}
        stateful = docs["StatefulSet"]
        assert stateful["spec"]["serviceName"] == docs["Service"]["metadata"]["name"]
        assert docs["Service"]["spec"]["clusterIP"] == "None"
        assert stateful["spec"]["volumeClaimTemplates"][0]["metadata"]["name"] == "data"
        database = stateful["spec"]["template"]["spec"]["containers"][0]
        env = {e["name"]: e for e in database["env"]}
        assert env["POSTGRES_PASSWORD_FILE"]["value"] == "/run/secrets/spl/postgres-password"
        assert not any("valueFrom" in e for e in database["env"])
        ingress = docs["NetworkPolicy"]["spec"]["ingress"]
        assert sorted(
            r["from"][0]["podSelector"]["matchLabels"]["app.kubernetes.io/name"] for r in ingress
        ) == sorted(STORES)
    else:
        assert "deploy/kubernetes/postgres.yaml" not in files


def test_no_secret_value_in_any_generated_file(generated) -> None:
    _, files, services = generated
    text = b"".join([*files.values(), *services.values()]).decode()
    assert not re.search(r"(?i)password\s*[:=]\s*['\"]?[A-Za-z0-9]{6,}", text)
    assert not re.search(r"TOKEN=(?!<secret>|\.\.\.)\S", text)  # placeholders only


def test_nothing_to_deploy_without_stores() -> None:
    resolved = product()
    for container in resolved.system.containers:
        container.stores.clear()
    assert deploy.generate(resolved) == {}
    assert service.generate(resolved) == {}


def test_names_yaml_would_read_as_other_values_stay_text() -> None:
    """A product called ``no`` and a store called ``null`` (both valid identifiers) were
    written bare: YAML read ``part-of: no`` as false and ``services: {null: ...}`` as a
    null key, and kubernetes-validate refused the Deployment. Every name reads back as
    the text it is, and every manifest passes ``kubernetes-validate --strict``."""
    import kubernetes_validate

    resolved = product(name="no", features=POSTGRES)
    store = next(s for c in resolved.system.containers for s in c.stores)
    store.name = "null"
    files = deploy.generate(resolved)
    compose = documents(files, "deploy/docker-compose.yml")[0]
    assert compose["name"] == "no" and "null" in compose["services"]
    manifests = [p for p in files if p.startswith("deploy/kubernetes/")]
    assert "deploy/kubernetes/null.yaml" in manifests
    for path in manifests:
        for document in documents(files, path):
            labels = document["metadata"].get("labels", {})
            assert labels.get("app.kubernetes.io/part-of", "no") == "no"
            kubernetes_validate.validate(document, "1.33.0", strict=True)
    deployment = next(
        d for d in documents(files, "deploy/kubernetes/null.yaml") if d["kind"] == "Deployment"
    )
    assert deployment["metadata"]["name"] == "null"
