// corpus/src/item_folder.hpp: an item's files, written into a hidden temporary folder in
// DIR/items/ and moved into place as a whole, so DIR/items/<id>/ is never half written.
#pragma once
#include <engine/cloud_io.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace corpus::detail {

class ItemFolder {
public:
    /// Creates DIR/items/.ladarvr-tmp-<pid>-<id> (O_EXCL by mkdir), registered for removal
    /// on SIGINT/SIGTERM (engine/cleanup.hpp); a killed run's is removed by the next run.
    /// Throws engine::Error("output: ...").
    ItemFolder(const std::filesystem::path& items, const std::string& id);
    /// Removes the temporary folder unless commit() moved it into place.
    ~ItemFolder();
    ItemFolder(const ItemFolder&) = delete;
    ItemFolder& operator=(const ItemFolder&) = delete;

    /// Where a file of the item is written before commit().
    std::filesystem::path path(const std::string& name) const;
    void writeText(const std::string& name, std::string_view content);
    void writeCloud(const std::string& name, const engine::PointCloud& cloud, engine::CloudFormat format);
    /// Moves the folder to DIR/items/<id>, replacing one a killed run left there (an
    /// atomic exchange, then the old one is removed).
    void commit();

private:
    void track(const std::string& name);
    std::filesystem::path items_, temp_, final_;
    std::string temp_name_, id_;
    int items_fd_ = -1, temp_fd_ = -1;
    std::vector<int> slots_;
    bool committed_ = false;
};

}  // namespace corpus::detail
