"""Inputs by URL (``s3://bucket/maps/a.xodr``, ``gs://…``, ``file://…``, ``memory://…``):
listing on the client and reading where a file is linted, through fsspec.

A utility below the pipeline, beside ``files.py``: it knows URLs, object stores and their
errors, nothing of linting. fsspec (and s3fs, botocore, …) are imported only when a URL
is listed or read, so a run over local files never pays for them. Credentials come from
where fsspec and the store's own library look (``AWS_*`` variables, ``~/.aws``, instance
roles, fsspec's config), never from xodrlint's options; every failure is a
:class:`RemoteError` carrying one line a person can act on.
"""

# No ``from __future__ import annotations``: every run imports this module (for
# ``is_url``), and a named tuple's quoted annotations cost 2 ms to compile when it is made.
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any, Final, NamedTuple

if TYPE_CHECKING:
    from fsspec import AbstractFileSystem

#: What installs each protocol's package, where xodrlint has an extra for it.
_EXTRA: Final = "pip install 'xodrlint[cloud]'"
_PACKAGE_OF_EXTRA: Final = frozenset({"fsspec", "s3fs"})

#: Protocols whose first path segment is a bucket: a missing one is said so.
_BUCKETED: Final = frozenset({"s3", "s3a", "gs", "gcs"})

#: botocore waits 60 s to connect and 60 s for each answer, tries 5 times, and s3fs
#: retries botocore's failures 5 times more: an endpoint that was down held a run for
#: minutes. Bounded here: 5 s to connect, 20 s for an answer, 3 attempts a request, all
#: retried by botocore (:func:`filesystem` turns s3fs's own retries off). fsspec's config
#: (``FSSPEC_S3``, ``~/.config/fsspec``) overrides any of these.
S3_DEFAULTS: Final[dict[str, Any]] = {
    "config_kwargs": {
        "connect_timeout": 5,
        "read_timeout": 20,
        "retries": {"total_max_attempts": 3, "mode": "standard"},
    },
}
#: botocore reads its retries from these too: where one is set, it decides.
_RETRY_VARIABLES: Final = ("AWS_MAX_ATTEMPTS", "AWS_RETRY_MODE")


class RemoteError(Exception):
    """A URL that cannot be listed or read; ``str()`` is one line, the URL not included.

    ``missing`` is set when the object or prefix is not there (but its bucket is): a
    glob then matches nothing rather than failing.
    """

    def __init__(self, reason: str, *, missing: bool = False) -> None:
        super().__init__(reason)
        self.missing = missing


class TooLarge(RemoteError):
    """The object holds more bytes than the reader's limit."""


class Listed(NamedTuple):
    """One object a listing found: its URL (spelt as the URL listed) and size in bytes."""

    url: str
    size: int | None


def is_url(text: str) -> bool:
    """Whether ``text`` names an input by URL (``scheme://…``), not a local path.

    A Windows drive (``C:\\maps``, ``C:/maps``) has a one-letter "scheme" and no ``//``,
    so it never reads as a URL. No regular expression: every run asks, and compiling one
    costs more than this check.
    """
    scheme, found, _ = text.partition("://")
    return (
        bool(found)
        and len(scheme) > 1
        and scheme.isascii()
        and scheme[0].isalpha()
        and all(char.isalnum() or char in "+.-" for char in scheme)
    )


def protocol_of(url: str) -> str:
    return url.split("://", 1)[0].lower()


def url_path(url: str) -> str:
    """The path part of ``url``, what ``--exclude`` globs match: the part after the bucket
    or host (``maps/tmp/a.xodr`` for ``s3://bucket/maps/tmp/a.xodr``).

    Split by hand: an object key may hold ``?`` or ``#``, which ``urlsplit`` would take
    for a query or a fragment.
    """
    return url.split("://", 1)[1].partition("/")[2]


def list_url(url: str) -> list[Listed]:
    """The object ``url`` names, or every object below it when it names a folder (a
    prefix), sorted by URL; each URL begins as ``url`` does (``s3://bucket/maps/x.xodr``
    below ``s3://bucket/maps``)."""
    fs, path = filesystem(url)
    with _Reasons(fs, path):
        info = fs.info(path)
        if info.get("type") != "directory":
            return [Listed(url, _size(info))]
    return _found(fs, url, path)


def list_below(url: str) -> list[Listed]:
    """Every object below the folder (prefix) ``url``, as :func:`list_url` spells them:
    one listing, where a glob's folder is concerned (an object store answers a prefix
    that holds nothing with an empty list, a missing bucket with an error)."""
    fs, path = filesystem(url)
    return _found(fs, url, path)


def _found(fs: "AbstractFileSystem", url: str, path: str) -> list[Listed]:
    with _Reasons(fs, path):
        found = fs.find(path, detail=True, withdirs=False)
    return sorted(
        Listed(_spelt_as(url, path, name, fs), _size(entry))
        for name, entry in found.items()
        if entry.get("type") == "file"
    )


def read_url(url: str, limit: int) -> bytes:
    """The bytes of the object ``url`` names; :class:`TooLarge` past ``limit`` bytes.

    One request for the first ``limit + 1`` bytes (``Range: bytes=0-limit`` on S3), not
    a HEAD for the size and a GET for the bytes: a worker's time per file on a store is
    its round trips. An empty object has no byte 0 to start a range at, which S3 answers
    with an error: only then is the size asked for.
    """
    fs, path = filesystem(url)
    with _Reasons(fs, path):
        try:
            data: bytes = fs.cat_file(path, start=0, end=limit + 1)
        except Exception as error:
            if not _unsatisfiable(error) or fs.size(path) != 0:
                raise
            data = b""
    if len(data) > limit:
        raise TooLarge("too large")
    return data


def shown_url(url: str) -> str:
    """``url`` as reports and messages show it: without the user name and password a URL
    may carry (``https://user:secret@host/…``), which every report would repeat."""
    scheme, found, rest = url.partition("://")
    if not found:
        return url
    authority, slash, below = rest.partition("/")
    if "@" not in authority:
        return url
    return f"{scheme}://{authority.rpartition('@')[2]}{slash}{below}"


def local_path(url: str) -> str | None:
    """The local path a ``file://`` URL names, ``None`` for any other URL."""
    if protocol_of(url) not in ("file", "local"):
        return None
    rest = url.split("://", 1)[1]
    return rest if rest.startswith("/") else "/" + rest.partition("/")[2]


def _unsatisfiable(error: Exception) -> bool:
    return any(_error_code(link) in ("InvalidRange", "416") for link in _chain(error))


def filesystem(url: str) -> "tuple[AbstractFileSystem, str]":
    """The fsspec filesystem for ``url`` and the path in it; :class:`RemoteError` when
    fsspec, or the package for the URL's protocol, is not installed."""
    protocol = protocol_of(url)
    try:
        from fsspec.core import url_to_fs
        from fsspec.registry import get_filesystem_class
    except ImportError:
        raise RemoteError(f"reading URLs needs fsspec ({_EXTRA})") from None
    try:
        kind = get_filesystem_class(protocol)
    except ValueError:
        raise RemoteError(f"no installed fsspec package reads {protocol}:// URLs") from None
    except ImportError as error:
        raise RemoteError(_missing_package(protocol, error)) from None
    options = storage_options(protocol)
    try:
        fs, path = url_to_fs(url, **options)
    except Exception as error:  # a third-party filesystem may raise anything on a bad URL
        raise RemoteError(reason(error)) from None
    if "s3" in _protocols(kind):
        fs.retries = 1  # botocore retries already: two layers would multiply the waits
    return fs, path


def _protocols(kind: type) -> tuple[str, ...]:
    names = getattr(kind, "protocol", ())
    return (names,) if isinstance(names, str) else tuple(names)


def _missing_package(protocol: str, error: ImportError) -> str:
    from fsspec.registry import known_implementations

    missing = getattr(error.__cause__, "name", None)
    if missing is None:  # the module fsspec's table names for the protocol
        known = known_implementations.get(protocol, {})
        missing = str(known.get("class", protocol)).split(".", 1)[0]
    package = str(missing).split(".", 1)[0]
    install = _EXTRA if package in _PACKAGE_OF_EXTRA else f"pip install {package}"
    return f"reading {protocol}:// URLs needs the package {package} ({install})"


def storage_options(protocol: str) -> dict[str, Any]:
    """What xodrlint asks of ``protocol``'s filesystem: timeouts for S3, under what
    fsspec's own config says (which wins, key by key, also inside ``config_kwargs``)."""
    import os

    from fsspec.config import conf  # filled at import, changed in place: read it now

    if protocol not in ("s3", "s3a"):
        return {}
    ours = {key: dict(value) for key, value in S3_DEFAULTS.items()}
    if any(name in os.environ for name in _RETRY_VARIABLES):
        del ours["config_kwargs"]["retries"]
    user = conf.get(protocol, {})
    merged = {**ours, **user}
    if isinstance(user.get("config_kwargs"), dict):
        merged["config_kwargs"] = {**ours["config_kwargs"], **user["config_kwargs"]}
    return merged


def _size(entry: dict[str, Any]) -> int | None:
    size = entry.get("size")
    return size if isinstance(size, int) else None


def _spelt_as(url: str, path: str, name: str, fs: "AbstractFileSystem") -> str:
    """``name`` (found below ``path``, which ``url`` names) as a URL written the way
    ``url`` is: the user's scheme and spelling of the folder, the store's names below."""
    base = path.rstrip("/")
    if name.startswith(base + "/"):
        return url.rstrip("/") + name[len(base) :]
    unstripped: str = fs.unstrip_protocol(name)
    return unstripped


class _Reasons:
    """Turns what a filesystem raises into a :class:`RemoteError` with one line.

    A context manager and not ``except`` clauses: filesystems raise their own types
    (botocore's, aiohttp's, …), which this module cannot import without importing them.
    """

    def __init__(self, fs: "AbstractFileSystem", path: str) -> None:
        self._fs = fs
        self._path = path

    def __enter__(self) -> None:
        return None

    def __exit__(self, kind: object, error: BaseException | None, trace: object) -> None:
        if error is None or isinstance(error, RemoteError) or not isinstance(error, Exception):
            return  # Ctrl-C and the like pass
        # a store that cannot be reached says nothing about its objects (fsspec's HTTP
        # filesystem raises FileNotFoundError for a refused connection)
        if _found_nothing(error) and not _unreachable(error):
            raise _not_found(self._fs, self._path, error) from None
        raise RemoteError(reason(error)) from None


def _unreachable(error: Exception) -> bool:
    names = {cls.__name__ for link in _chain(error) for cls in type(link).__mro__}
    return bool(names & _UNREACHABLE)


#: Errors (by class name: their packages are not imported here) of a store out of reach.
_UNREACHABLE: Final = frozenset(
    {
        "ConnectionError",  # refused, reset: OSError's subclasses of that name
        "ClientConnectorError",
        "EndpointConnectionError",
        "ConnectTimeoutError",
        "ConnectionTimeoutError",
        "TimeoutError",
    }
)


def _found_nothing(error: Exception) -> bool:
    return any(isinstance(link, FileNotFoundError) for link in _chain(error))


def _not_found(fs: "AbstractFileSystem", path: str, error: Exception) -> RemoteError:
    """No such bucket (exit 2, also for a glob) or no such object (a glob matches none)."""
    protocol = _protocols(type(fs))[0] if _protocols(type(fs)) else ""
    if protocol in ("file", "local"):
        return RemoteError("no such file or directory", missing=True)
    bucket = path.strip("/").split("/", 1)[0]
    if protocol in _BUCKETED and bucket and _no_bucket(fs, bucket, error):
        return RemoteError(f"no such bucket '{bucket}'")
    return RemoteError("no such object", missing=True)


def _no_bucket(fs: "AbstractFileSystem", bucket: str, error: Exception) -> bool:
    if any(_error_code(link) == "NoSuchBucket" for link in _chain(error)):
        return True
    try:  # a HEAD without a body ("404") does not say what is missing: ask
        return not fs.exists(bucket)
    except Exception:  # no answer is no proof that the bucket is missing
        return False


def _chain(error: BaseException) -> Iterator[BaseException]:
    """``error`` and what caused it, outermost first (each once: chains can loop)."""
    seen: set[int] = set()
    link: BaseException | None = error
    while link is not None and id(link) not in seen:
        seen.add(id(link))
        yield link
        link = link.__cause__ or link.__context__


def _error_code(error: BaseException) -> str | None:
    """The store's error code of a botocore ``ClientError`` (``NoSuchBucket``, ``403``)."""
    response = getattr(error, "response", None)
    if isinstance(response, dict):
        code = response.get("Error", {}).get("Code")
        return str(code) if code is not None else None
    return None


#: Store error codes, by what they mean to the person running xodrlint.
_DENIED_CODES: Final = frozenset({"AccessDenied", "403", "AllAccessDisabled", "Forbidden"})
_REFUSED_CREDENTIALS: Final = frozenset(
    {"InvalidAccessKeyId", "SignatureDoesNotMatch", "ExpiredToken", "InvalidToken"}
)
_NO_CREDENTIALS: Final = (
    "no credentials found (AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY, ~/.aws/credentials,"
    " or an instance role)"
)


def reason(error: BaseException) -> str:
    """Why ``error`` happened, as one line: what the store said, or what the network did."""
    links = list(_chain(error))
    names = {cls.__name__ for link in links for cls in type(link).__mro__}
    for link in links:
        code = _error_code(link)
        if code == "NoSuchBucket":
            return "no such bucket"
        if code in ("NoSuchKey", "404"):
            return "no such object"
        if code in _DENIED_CODES:
            return "access denied"
        if code in _REFUSED_CREDENTIALS:
            return f"access denied: the credentials were refused ({code})"
    where = _endpoint(links)
    if "NoCredentialsError" in names:
        return _NO_CREDENTIALS
    if any(isinstance(link, ConnectionRefusedError) for link in links):
        return f"connection refused{where}"
    if "ConnectTimeoutError" in names or "ConnectionTimeoutError" in names:
        return f"timed out connecting{where}"
    if "ReadTimeoutError" in names or any(isinstance(link, TimeoutError) for link in links):
        return f"timed out waiting for an answer{where}"
    if "EndpointConnectionError" in names:
        return f"cannot connect{where}"
    if any(isinstance(link, PermissionError) for link in links):
        return "access denied"
    return _one_line(f"{type(error).__name__}: {error}" if str(error) else type(error).__name__)


def _endpoint(links: list[BaseException]) -> str:
    """`` to host:port`` of the endpoint a botocore error names, or nothing."""
    for link in links:
        found = getattr(link, "kwargs", {}).get("endpoint_url")
        if isinstance(found, str) and "://" in found:
            return " to " + found.split("://", 1)[1].split("/", 1)[0]
    return ""


def _one_line(text: str) -> str:
    return " ".join(text.split())
