// The "New map, building or floor" panel: a building of your own from scratch in the viewer
// (docs/your-building.md), through the same REST calls as `locus map create` and the others.
// Writes send the API key; without one (on a keyed server) the key field is asked for.
import { postWrite } from './api.js';

const $ = (id) => document.getElementById(id);

export function installCreatePanel(viewer, { mapCreated, buildingCreated, floorCreated }) {
  async function create(path, body, what, then) {
    try {
      const made = await postWrite(path, body);
      viewer.status(`Created ${what} '${made.name}'.`);
      await then(made);
    } catch (e) {
      if (e.status === 401) viewer.askKey(`Creating ${what} needs the API key: enter it below.`);
      else viewer.status(`Error: ${e.message}`);
    }
  }
  $('new-map').addEventListener('submit', (e) => {
    e.preventDefault();
    create('/v1/maps', { name: $('new-map-name').value.trim() }, 'map', (m) => mapCreated(m.id));
  });
  $('new-building').addEventListener('submit', (e) => {
    e.preventDefault();
    if (!viewer.mapId()) return viewer.status('Create or choose a map first.');
    create(`/v1/maps/${viewer.mapId()}/buildings`, { name: $('new-building-name').value.trim() }, 'building',
      (b) => buildingCreated(b.id));
  });
  $('new-floor').addEventListener('submit', (e) => {
    e.preventDefault();
    const building = viewer.buildingId();
    if (!building) return viewer.status('Create or choose a building first.');
    create(`/v1/buildings/${building}/floors`, {
      name: $('new-floor-name').value.trim(), level: Number($('new-floor-level').value),
      width: Number($('new-floor-width').value), height: Number($('new-floor-height').value),
    }, 'floor', (f) => floorCreated(f.building_id, f.id));
  });
}
