# The console: the dashboard built with Node, served by the Python backend.
FROM node:20-bookworm-slim AS dashboard
WORKDIR /src/frontend
COPY frontend/package.json frontend/package-lock.json ./
RUN npm ci --no-audit --no-fund --loglevel=error
COPY frontend/ ./
RUN npm run build

FROM python:3.11-slim-bookworm
WORKDIR /app
COPY idl/ idl/
COPY backend/ backend/
# the UMAA types are generated from idl/ (never committed; sem_console.idlgen) before the backend is installed
RUN pip install --no-cache-dir "$(grep -o 'cyclonedds==[0-9.]*' backend/pyproject.toml)" \
 && PYTHONPATH=backend python -m sem_console.idlgen \
 && pip install --no-cache-dir ./backend
COPY --from=dashboard /src/frontend/dist /app/frontend/dist
# the database a URL (not SEM_DB_PATH): an operations centre station replaces it with its postgresql:// one
ENV SEM_FRONTEND_DIR=/app/frontend/dist SEM_HOST=0.0.0.0 SEM_PORT=8000 SEM_DATABASE_URL=/data/sem-console.sqlite3
VOLUME /data
EXPOSE 8000
HEALTHCHECK --interval=10s --timeout=3s --start-period=20s \
  CMD python -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:8000/api/health', timeout=2)"
CMD ["sem-console"]
