"""`joshua-dataset view DIR`: a local page listing a dataset's episodes with their video, task and joint plots.

Routes (read-only; loopback by default):
- `GET /`: the page (view_page.html, no outside resources);
- `GET /api/dataset`: dataset_info.describe() plus, per episode, its videos (`{key: {"url", "from_s",
  "to_s"}}`: v3.0 keeps several episodes in one mp4, so the page plays the episode's span of it);
- `GET /api/episodes/<index>`: the episode's joint series, `{"names": {feature: [joint ...]},
  "series": {feature: [[value per joint] per frame]}, "fps"}` for `action` and `observation.state`;
- `GET /videos/...`: the dataset's video files (range requests served).
"""

from pathlib import Path

import pyarrow.parquet as pq

from joshua_runtime.datasets.dataset_info import EPISODES_DIRECTORY, describe, read_info

PAGE = Path(__file__).with_name("view_page.html")
JOINT_FEATURES = ("action", "observation.state")
VIDEO_ROUTE = "/videos"


def episode_rows(root: Path) -> list[dict]:
    rows = []
    for path in sorted((root / EPISODES_DIRECTORY).rglob("*.parquet")):
        rows.extend(pq.read_table(path).to_pylist())
    return sorted(rows, key=lambda row: row["episode_index"])


def videos_of(info: dict, row: dict) -> dict:
    videos = {}
    for key, spec in info["features"].items():
        if spec["dtype"] != "video":
            continue
        relative = info["video_path"].format(
            video_key=key,
            chunk_index=row[f"videos/{key}/chunk_index"],
            file_index=row[f"videos/{key}/file_index"],
        )
        videos[key] = {
            "url": f"{VIDEO_ROUTE}/{Path(relative).relative_to('videos').as_posix()}",
            "from_s": row[f"videos/{key}/from_timestamp"],
            "to_s": row[f"videos/{key}/to_timestamp"],
        }
    return videos


def joint_series(root: Path, info: dict, row: dict) -> dict:
    path = root / info["data_path"].format(chunk_index=row["data/chunk_index"], file_index=row["data/file_index"])
    features = [name for name in JOINT_FEATURES if name in info["features"]]
    table = pq.read_table(path, columns=["episode_index", "frame_index", *features])
    frames = sorted(
        (r for r in table.to_pylist() if r["episode_index"] == row["episode_index"]), key=lambda r: r["frame_index"]
    )
    return {
        "fps": info["fps"],
        "names": {name: info["features"][name].get("names") for name in features},
        "series": {name: [r[name] for r in frames] for name in features},
    }


def create_app(root: Path):
    from starlette.applications import Starlette
    from starlette.responses import HTMLResponse, JSONResponse
    from starlette.routing import Mount, Route
    from starlette.staticfiles import StaticFiles

    info = read_info(root)

    async def page(_request):
        return HTMLResponse(PAGE.read_text())

    async def dataset(_request):
        described = describe(root)
        rows = {row["episode_index"]: row for row in episode_rows(root)}
        for episode in described["episodes"]:
            episode["videos"] = videos_of(info, rows[episode["index"]])
        return JSONResponse(described)

    async def episode(request):
        rows = {row["episode_index"]: row for row in episode_rows(root)}
        index = request.path_params["index"]
        if index not in rows:
            return JSONResponse({"error": f"no episode {index}"}, status_code=404)
        return JSONResponse(joint_series(root, info, rows[index]))

    routes = [
        Route("/", page),
        Route("/api/dataset", dataset),
        Route("/api/episodes/{index:int}", episode),
    ]
    if (root / "videos").is_dir():
        routes.append(Mount(VIDEO_ROUTE, StaticFiles(directory=root / "videos")))
    return Starlette(routes=routes)


def serve(root: Path, bind: str, port: int) -> str:
    """Serve the page until Ctrl-C; prints its URL first. Returns the last line to print."""
    import socket

    import uvicorn

    app = create_app(root)
    listener = socket.create_server((bind, port))
    host, chosen = listener.getsockname()[:2]
    print(f"viewing {root} at http://{host}:{chosen}/ (Ctrl-C stops)", flush=True)
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", lifespan="off"))
    server.run(sockets=[listener])
    return f"stopped viewing {root}"
