#pragma once
// Soft-branch resistance per metre of pin as a function of use (paper section 3.1, Table 2), and the
// extension terms a fitted model adds. The model is data: the species file names it, and an extended
// species file carries its terms; no code changes to switch.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "components/insertion.hpp"

namespace ikebana::systems::insertion {

// Values a term may depend on besides the insertion count: trial covariates or world settings.
// A numeric value of NaN, or a category of "", is absent (a map kept from tick to tick on the 1 kHz
// lane marks what an insertion lacks this way rather than erase and remake the entry).
struct Covariates {
    std::map<std::string, double> numeric;
    std::map<std::string, std::string> category;
};

// Expands a measured table by a named model into per-insertion values (index k-1 for insertion k,
// the last value holding from then on):
//   paper_baseline  - insertions 1 and 2 as measured, the mean of insertions 3..6 from the third on
//                     (the paper's own model: it calls 3..6 experimental error);
//   table_hold_last - the table as measured;
//   none            - the first value for ever.
// An unknown model name gives an empty vector.
std::vector<double> expand_deterioration(const std::string& model, const std::vector<double>& table);

// exp(sum of terms) for these covariates; 1 when there are no terms. "insertion" is always available.
// A numeric covariate the world does not have is taken at the centre of the range its term was fitted
// on (missing_covariates says which; leaving the term out would put the force where no data was, e.g.
// 18 gf a pin for a species fitted at 100), a category at its reference level.
// The factor multiplies the resistance of either branch kind (soft table or hard Eq. 6); it is kept
// within e^-5..e^5, and a non-finite sum counts as 0.
double extension_factor(const std::vector<components::DeteriorationTerm>& terms, std::uint32_t insertion,
                        const Covariates& covariates);
// The sum of terms itself, before the factor's clamp (a non-finite sum counts as 0): what a fit needs
// of one term at coefficient 1, whose sum may lie far outside +-5 (a power of 2 over 1..6 reaches 36).
double extension_exponent(const std::vector<components::DeteriorationTerm>& terms, std::uint32_t insertion,
                          const Covariates& covariates);

// Covariates the insertion systems set themselves on every insertion (InsertionResistanceSystem).
bool set_on_every_insertion(const std::string& covariate);

// A column an extension reads that neither the world's covariates nor the insertion itself sets, and
// what is used instead: a number at the centre of its fitted range, or a category's reference level.
struct MissingCovariate {
    std::string name;
    bool numeric = true;
    double value = 0.0;            // numeric: what is used
    double low = 0.0, high = 0.0;  // numeric: the range the term holds over
};
std::vector<MissingCovariate> missing_covariates(const std::vector<components::DeteriorationTerm>& terms, const Covariates& world);

// The basis value of one term's form at x (already less the term's origin); used by the fit as well
// as by the model, so the two cannot disagree.
double term_basis(const std::string& form, double x, double scale);

// Resistance per metre of pin at the k-th insertion (k >= 1) of a sound stem end.
// `extended` false: the base model's alone (an extension that applies to the push, for the holding).
double soft_resistance_n_per_m(const components::PinResistance& model, std::uint32_t insertion, const Covariates& covariates = {}, bool extended = true);

} // namespace ikebana::systems::insertion
