// open_paged_mvx (megavox/trace.h): a PagedDag whose reader copies pages out of the mapped file.
#include <memory>

#include "io/mvx_pages.h"
#include "megavox/error.h"
#include "megavox/trace.h"

namespace mv {

PagedDag open_paged_mvx(const std::string& path) {
  auto file = std::make_shared<const MvxPages>(path);
  PagedDag d;
  d.grid = file->grid();
  d.bounds = file->bounds();
  d.encoding = file->encoding();
  d.levels = file->levels();
  d.page_words = file->page_words();
  d.pages = file->pages();
  d.level_starts = file->level_starts();
  d.has_colours = file->has_colours();
  d.colour_entries = file->colour_entries();
  d.voxels = file->voxels();
  d.words = file->words();
  d.read = [file](uint32_t page, std::span<uint32_t> words) {
    std::string error;
    if (!file->read_page(page, words, &error)) throw Error(error);
  };
  if (file->has_colours() && file->plane_words() != 0) {
    d.plane_words = file->plane_words();
    d.read_sizes = [file](uint32_t page, std::span<uint32_t> words) {
      std::string error;
      if (!file->read_sizes(page, words, &error)) throw Error(error);
    };
    d.colour = [file](uint64_t e) { return file->colour(e); };
  }
  return d;
}

bool is_paged_mvx(const std::string& path) { return MvxPages::is_paged(path); }

}  // namespace mv
