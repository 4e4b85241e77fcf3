"""A node's HTTP client of its store (docs/services.md, "Robot-side writers and
readers"): JSON over http or https only, the bearer token from the environment, an
https service verified against the system's authorities or the one file the product
names. The product's names arrive as a ``StoreAccess``.
"""

from __future__ import annotations

import json
import os
import ssl
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar


@dataclass(frozen=True)
class StoreAccess:
    """What a node knows of its store, as its generated ``store_client.py`` says it."""

    name: str  # the store's resources are under /<name>
    token_env: str  # the variable of the bearer token (never a file)
    ca_env: str  # the variable naming a certificate authority's file for https
    collection: str  # "records" for a writer, the refined type a reader reads
    fields: dict[str, str]  # field name -> double | int | string | bool


class StoreError(Exception):
    """The service answered with an error status (``status``) or could not be reached."""

    def __init__(self, status: int | None, message: str) -> None:
        super().__init__(f"{status or 'unreachable'}: {message}")
        self.status = status

    @property
    def retryable(self) -> bool:
        return self.status is None or self.status >= 500 or self.status == 429


class StoreURLError(ValueError):
    """A store URL that is not http(s): no file:, ftp: or other scheme is ever opened."""

    def __init__(self, store: str, message: str) -> None:
        super().__init__(message)
        self.store = store


class StoreClient:
    def __init__(
        self,
        access: StoreAccess,
        base_url: str,
        token: str | None = None,
        timeout: float = 10.0,
    ) -> None:
        scheme = urllib.parse.urlsplit(base_url).scheme
        if scheme not in ("http", "https"):
            message = f"store URL {base_url!r}: only http and https are used"
            raise StoreURLError(access.name, message)
        self.access = access
        self.base = base_url.rstrip("/") + "/" + access.name
        self.token = token if token is not None else os.environ.get(access.token_env, "")
        self.timeout = timeout
        self.context = (
            ssl.create_default_context(cafile=os.environ.get(access.ca_env) or None)
            if scheme == "https"
            else None
        )

    def _request(self, method: str, url: str, body: Any = None) -> Any:
        headers = {"Accept": "application/json"}
        data = None
        if body is not None:
            data = json.dumps(body, allow_nan=False).encode()
            headers["Content-Type"] = "application/json"
        if self.token:
            headers["Authorization"] = f"Bearer {self.token}"
        request = urllib.request.Request(url, data=data, method=method, headers=headers)
        try:
            # the scheme is http or https (checked above): no file: or ftp: URL is opened
            with urllib.request.urlopen(  # nosec B310
                request, timeout=self.timeout, context=self.context
            ) as response:
                return json.loads(response.read() or b"null")
        except urllib.error.HTTPError as error:
            detail = error.read().decode("utf-8", "replace")
            raise StoreError(error.code, detail) from error
        except (urllib.error.URLError, OSError) as error:
            raise StoreError(None, str(error)) from error

    def post(self, records: list[dict[str, Any]]) -> list[int]:
        """Store ``{"robot", "timestamp", "data"}`` records in one all-or-nothing batch."""
        answer = self._request("POST", self.base + "/records/batch", {"records": records})
        return list(answer["ids"])

    def read(
        self,
        start: float | None = None,
        end: float | None = None,
        robot: str | None = None,
        after_id: int | None = None,
        limit: int = 500,
    ) -> list[dict[str, Any]]:
        """All records of the collection in the range, following the pages."""
        query: dict[str, str | int] = {"limit": limit}
        if start is not None:
            query["from"] = repr(float(start))
        if end is not None:
            query["to"] = repr(float(end))
        if robot is not None:
            query["robot"] = robot
        if after_id is not None:
            query["after_id"] = after_id
        url = f"{self.base}/{self.access.collection}?{urllib.parse.urlencode(query)}"
        items: list[dict[str, Any]] = []
        while url:
            page = self._request("GET", url)
            items += page["items"]
            following = page.get("next")
            url = urllib.parse.urljoin(url, following) if following else ""
        return items


Client = TypeVar("Client", bound=StoreClient)


def client_for(make: Callable[[str], Client], url: str) -> Client:
    """The node's client (``make``: its product's StoreClient) of the store at ``url``,
    or, for a URL that is not http(s), the node stops at start-up with a message saying
    which URL and what to give instead."""
    try:
        return make(url)
    except StoreURLError as error:
        raise SystemExit(
            f"{error}; set the store_url parameter to the http:// or https:// URL of "
            f"the {error.store} service"
        ) from None
