// pcd_writer: PCD v0.7, binary or ascii, in a stream (docs/formats.md). The optional fields
// use PCL's names and the smallest PCL type that holds them; rgb is PCL's packed float.
#include "counted_writer.hpp"

namespace io::detail {

namespace {

// One optional field in PCD: its name, TYPE (U or F) and SIZE.
struct PcdField {
    const char* name;
    char type;
    int size;
};

PcdField pcdField(OptionalField f) {
    switch (f) {
        case OptionalField::Label: return {"label", 'U', 1};
        case OptionalField::View: return {"view", 'U', 2};
        case OptionalField::Range: return {"range", 'F', 4};
        case OptionalField::Intensity: return {"intensity", 'U', 2};
        case OptionalField::ReturnNumber: return {"return_number", 'U', 1};
        case OptionalField::Returns: return {"number_of_returns", 'U', 1};
        case OptionalField::Incidence: return {"incidence_deg", 'F', 4};
        case OptionalField::ScanAngle: return {"scan_angle_deg", 'F', 4};
        case OptionalField::Height: return {"height_above_ground_m", 'F', 4};
    }
    return {"label", 'U', 1};
}

// The header, with paddedCount(0) for WIDTH and POINTS (their offsets in `count_at`).
std::string pcdHeader(bool ascii, const glm::dvec3& origin, const core::CloudFields& fields,
                      std::vector<long>& count_at) {
    std::string names = "x y z", sizes = "4 4 4", types = "F F F", counts = "1 1 1";
    auto add = [&](const char* n, int s, char t) {
        names += std::string(" ") + n;
        sizes += " " + std::to_string(s);
        types += std::string(" ") + t;
        counts += " 1";
    };
    if (fields.rgb) add("rgb", 4, 'F');
    for (OptionalField f : optionalFields(fields)) {
        const PcdField p = pcdField(f);
        add(p.name, p.size, p.type);
    }
    const std::string zero = paddedCount(0);
    std::string h = "# .PCD v0.7 - Point Cloud Data file format (ladarvr: world = origin + (x, y, z))\n";
    h += "# ladarvr origin " + originText(origin) + "\n";
    h += "VERSION 0.7\nFIELDS " + names + "\nSIZE " + sizes + "\nTYPE " + types + "\nCOUNT " + counts + "\nWIDTH ";
    count_at.push_back(long(h.size()));
    h += zero + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS ";
    count_at.push_back(long(h.size()));
    h += zero + "\n";
    h += ascii ? "DATA ascii\n" : "DATA binary\n";
    return h;
}

// The record's size for `fields`.
std::size_t pcdRecordBytes(const core::CloudFields& fields) {
    std::size_t n = 12 + (fields.rgb ? 4 : 0);
    for (OptionalField f : optionalFields(fields)) n += std::size_t(pcdField(f).size);
    return n;
}

class PcdWriter final : public RecordWriter<PcdWriter> {
  public:
    PcdWriter(platform::TempFile& file, bool ascii, std::string header, std::vector<long> count_at,
              const core::CloudFields& fields)
        : RecordWriter(file, std::move(header), std::move(count_at), ascii, pcdRecordBytes(fields)), fields_(fields) {}

  private:
    friend class RecordWriter<PcdWriter>;

    void binary(char*& out, const core::CloudPoint& p) const {
        const core::CloudFields& f = fields_;
        putRaw(out, p.position.x);
        putRaw(out, p.position.y);
        putRaw(out, p.position.z);
        if (f.rgb) putRaw(out, std::uint32_t(p.rgb & 0xFFFFFFu));  // PCL's packed float: the same 4 bytes
        putBinaryFields<std::uint16_t, std::uint16_t>(out, p, f);
    }

    // binary()'s record back into a point.
    void unbinary(const char*& in, core::CloudPoint& p) const {
        p = core::CloudPoint{};
        p.position.x = getRaw<float>(in);
        p.position.y = getRaw<float>(in);
        p.position.z = getRaw<float>(in);
        if (fields_.rgb) p.rgb = getRaw<std::uint32_t>(in);
        getBinaryFields<std::uint16_t, std::uint16_t>(in, p, fields_);
    }

    void text(std::string& s, const core::CloudPoint& p) const {
        const core::CloudFields& f = fields_;
        putFloat(s, p.position.x);
        s += ' ';
        putFloat(s, p.position.y);
        s += ' ';
        putFloat(s, p.position.z);
        if (f.rgb) {
            // The packed float as a (tiny) float number: PCL's and Open3D's ASCII readers
            // parse a TYPE F field as a float and keep its bits.
            const std::uint32_t rgb = p.rgb & 0xFFFFFFu;
            float packed;
            std::memcpy(&packed, &rgb, 4);
            s += ' ';
            putFloat(s, packed);
        }
        putTextFields(s, p, f);
    }

    core::CloudFields fields_;
};

}  // namespace

std::unique_ptr<FormatWriter> openPcdWriter(platform::TempFile& file, bool ascii, const glm::dvec3& origin,
                                            const core::CloudFields& fields) {
    std::vector<long> count_at;
    std::string header = pcdHeader(ascii, origin, fields, count_at);
    return std::make_unique<PcdWriter>(file, ascii, std::move(header), std::move(count_at), fields);
}

}  // namespace io::detail
