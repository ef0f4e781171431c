//! The claim table: every claim of the paper's results sections (§2–§8) and conclusions (§9),
//! one row each, the sentence quoted in full (Zhang, Thiers-Moggia, Málaga-Chuquitaype, Bull.
//! Earthquake Eng. 2022). The rows' measurements live in the rows_* modules, in this order.

/// One claim of the paper.
pub struct Claim {
    pub id: &'static str,
    pub figure: &'static str,
    pub claim: &'static str,
}

const fn c(id: &'static str, figure: &'static str, claim: &'static str) -> Claim {
    Claim { id, figure, claim }
}

pub const CLAIMS: &[Claim] = &[
    // §2
    c(
        "fig3-restitution-grows",
        "Fig. 3",
        "The plot shows that as the apparent mass of the inerter increases, the coefficient r_σ becomes larger, indicating a lower amount of energy dissipation during impact.",
    ),
    c(
        "fig3-stocky",
        "Fig. 3",
        "Importantly, this effect is much more significant for stocky structures.",
    ),
    // §3
    c(
        "fig5-converge",
        "Fig. 5a",
        "This is evident in Fig. 5a, where the rotation responses obtained with Housner's formulation and the Dirac-Delta model converge when n = 0.0001.",
    ),
    c(
        "fig5-spikes",
        "Fig. 5b",
        "Moreover, the acceleration spikes predicted by the classical formulation are clearly observed in Fig. 5b.",
    ),
    c(
        "fig5-spikes-disappear",
        "Fig. 5b",
        "As the impact forces become more distributed over time (n = 0.005), these spikes disappear and the acceleration history approaches the in-between-impacts response obtained with Housner's model.",
    ),
    c(
        "fig5-similar-rotation",
        "Fig. 5",
        "Likewise, very similar rotation amplitudes are obtained with the three models under consideration, even though changes in the duration of impact cause shifts in the phase of the response.",
    ),
    // §5.2
    c(
        "fig8-inerter-stabilizes",
        "Fig. 8a",
        "It is clear from Fig. 8a that the inerter (σ = 0.5) can greatly stabilize the block during the initial stages of the response.",
    ),
    c(
        "fig8-inerter-amplified-later",
        "Fig. 8a",
        "However, the response is amplified at later stages, relative to the uncontrolled structure (σ = 0), which indicates a lower amount of energy dissipation during impact and/or energy being transferred back from the inerter to the structure.",
    ),
    c(
        "fig8-clutch-eliminates",
        "Fig. 8b",
        "On the other hand, Fig. 8b proves that the inclusion of one-way clutches can eliminate this phenomenon and improve the effectiveness of inerters.",
    ),
    c(
        "fig8-faster-decrease",
        "Fig. 8b",
        "In addition, it can be appreciated from Fig. 8b that the sequential clutch formulation leads to a faster amplitude decrease in comparison with the newly proposed model.",
    ),
    c(
        "fig9-weak-reengagement",
        "Fig. 9a",
        "It is also clear from Fig. 9a that the model proposed in this paper struggles to attain a strong re-engagement with the structure after t = 3s.",
    ),
    c(
        "fig9-sequential-reengages",
        "Fig. 9b",
        "The sequential model (Fig. 9b), on the other hand, re-engages irrespectively of the conditions of relative motion until the rocking block comes to rest.",
    ),
    c(
        "fig10-intensive-engagement",
        "Figs. 9a, 10",
        "It should be noted that the apparently solid areas depicted in Fig. 9a for the newly proposed model corresponds to regions of intensive engagement-disengagement activity.",
    ),
    // §5.3
    c(
        "fig11-comparable-peaks",
        "Fig. 11",
        "Figure 11 shows that the newly adopted model and the previously proposed sequential model achieve comparable peak displacement responses.",
    ),
    c(
        "fig11-inerter-slightly-higher",
        "Fig. 11",
        "By comparison, rocking blocks equipped with a single inerter without clutch reach a slightly higher peak displacement, …",
    ),
    c(
        "fig11-energy-back-and-forth",
        "Fig. 11",
        "… and transfer energy back and forth between the inerter and the structure leading to marked peaks and troughs in the structure's energy levels and a suboptimal performance.",
    ),
    c(
        "s53-mechanistic-may-dissipate-more",
        "§5.3",
        "In other words, … it is possible that the proposed model can achieve greater energy dissipation than the sequential idealization even though the engagement time is shorter.",
    ),
    c(
        "fig12-overturning",
        "Fig. 12",
        "In these plots, the condition of overturning is attained when frequency ratio is approximately ωg/p < 3 and the curves are discontinued after that.",
    ),
    c(
        "fig12-largely-comparable",
        "Fig. 12",
        "It is clear from 12 that when looked in terms of peak response values, both the detailed model presented in this paper and the previous sequential idealization produce largely comparable maximum displacement results.",
    ),
    c(
        "fig12-marginally-lower",
        "Fig. 12",
        "For low frequency ratios, the more faithful representation of the of clutch in the new model leads to displacement estimations marginally lower than the sequential model.",
    ),
    c(
        "fig12-trend",
        "Fig. 12",
        "These differences are further reduced as the frequency ratio increases.",
    ),
    c(
        "fig12-acceleration",
        "Fig. 12",
        "On the other hand, the effects of a more detailed simulation of the clutch engagement process leads to higher acceleration levels, due to the juddering effects described above, and produce peak values of acceleration markedly larger than the ideally sequential assumption.",
    ),
    c(
        "fig12-suppression",
        "§5.3, Fig. 12",
        "It appears that the most effective way to control peak responses in rigid rocking blocks is by increasing the suppression coefficient of the inerter.",
    ),
    // §9 on rigid blocks
    c(
        "s9-restitution-slender",
        "§9",
        "Importantly, this effect was found not to be significant in slender blocks, although it can affect the efficiency of the proposed strategy when high apparent mass ratios or nonslender structures are considered.",
    ),
    c(
        "s9-dirac-window",
        "§9",
        "Using an alternative formulation based on Dirac-Delta forces, it was demonstrated that the infinite acceleration spikes predicted by Housner's model can be ignored under the assumption that impact forces are sufficiently distributed over time as to cause continuous velocity transitions, but sharp enough not to appreciably affect the rotation response.",
    ),
    c(
        "s9-clutch-below-single",
        "§9",
        "The results of the analyses showed that the blocks equipped with clutched inerters experienced lower rotation demands in comparison with their single-inerter counterparts, thus confirming the advantages of incorporating a clutch.",
    ),
    c(
        "s9-clutch-larger-acceleration",
        "§9",
        "In terms of accelerations, however, the intensive engagement-disengagement behaviour mentioned above had a detrimental effect, resulting in larger demands for the structures equipped with clutched inerters.",
    ),
    c(
        "s9-protected-smaller",
        "§9",
        "Nevertheless, it should be noted that in all cases the inerter-equipped structures experienced smaller rotation and accelerations demands than unprotected ones.",
    ),
    // §3–§5: the mechanisms around Figs. 5, 6, 9 and 10 (rows_mechanisms)
    c(
        "fig5-phase-shift",
        "Fig. 5",
        "… even though changes in the duration of impact cause shifts in the phase of the response.",
    ),
    c(
        "fig5-equivalent-dissipation",
        "Fig. 5",
        "The magnitude of the impact forces is defined based on Housner's coefficient of restitution, r, according to Eq. 18. Accordingly, the three models compared in Fig. 5 have equivalent energy dissipation ratios during impact.",
    ),
    c(
        "fig6-epsilon-distortion",
        "Fig. 6",
        "… where ϵ is a factor that controls the transition between engagement and disengagement. As can be appreciated from Fig. 6, a higher value of ϵ avoids the local distortion near negative zero.",
    ),
    c(
        "s4-reset-needed",
        "§4",
        "Therefore, the local coordinate is updated in real time by resetting its value to the structure's local coordinate once a re-engagement event is detected. … If this is not done, then the clutch will be prevented from re-engaging after the first engagement event.",
    ),
    c(
        "fig9-sudden-loss",
        "Fig. 9",
        "Figure 9 evidences the effects of the underlying assumption of the sequential model related to the complete sudden loss of the energy in inerter after disengagement. This contrasts with the relatively decelerated response of the newly proposed model which is controlled by an explicit modelling of the viscous dissipation within the device.",
    ),
    c(
        "fig9-limited-time",
        "Fig. 9a",
        "This is because at this stage in the response the inerter has limited time to decelerate while the frequency of the rocking motion continues to increase rapidly.",
    ),
    c(
        "fig10-coincide",
        "Fig. 10",
        "When the velocity of the inerter and the local velocity in the structure coincide (Point B), a maximum displacement difference and peak transmission is achieved.",
    ),
    // §6.2
    c(
        "fig14-inerter-uplift",
        "Fig. 14",
        "Figure 14 demonstrates that the introduction of a single inerter without clutch can significantly reduce the peak base uplift rotation …",
    ),
    c(
        "fig14-inerter-deformation",
        "Fig. 14",
        "… but has negligible effects on the elastic deformations of the column.",
    ),
    c(
        "fig14-inerter-acceleration",
        "Fig. 14",
        "The horizontal acceleration levels are also benefited by the additional inertia provided by the single inerter.",
    ),
    c(
        "fig14-clutch-further",
        "Fig. 14",
        "The addition of clutches can further reduce the peak uplift rotation and horizontal drift, …",
    ),
    c(
        "fig14-clutch-deformation",
        "Fig. 14",
        "… but only a small improvement in the structure's deformation is observed.",
    ),
    c(
        "fig14-quick-rest",
        "Fig. 14",
        "However, the structure equipped with clutched inerter has far more efficient energy dissipation than single inerter, which makes the structure quickly reach rest from peak response.",
    ),
    c(
        "fig14-clutch-acceleration",
        "Fig. 14",
        "Although clutched inerters can improve displacement response, they appear less effective in controlling peak horizontal accelerations under single pulses and larger acceleration values than with the single inerter configuration are observed.",
    ),
    // §6.3
    c(
        "fig15-inerter-returns",
        "Fig. 15c, d",
        "It can be seen in this figure that, for a structure with single inerters, part of the inerter's energy transferred back to the structure during the rocking motion as shown in Fig. 15c and d.",
    ),
    c(
        "fig15-clutch-prevents",
        "Fig. 15e, f",
        "… and Fig. 15e and f prove that the clutch can fully prevent the energy stored in inerter from being transferred back to structure.",
    ),
    c(
        "fig15-damping-improves",
        "Fig. 15d",
        "It is worth mentioning that the damping inside the inerter can also improve the energy dissipation …",
    ),
    c(
        "fig15-xi-similar",
        "Fig. 15b",
        "It should also be noted that the proposed inerter model with a normalized damping ratio of ξθ = 0.02 has similar dissipating capacity than the sequential model used by Thiers-Moggia and Málaga-Chuquitaype (2020a).",
    ),
    c(
        "fig16-rocking-dominated",
        "Fig. 16",
        "This figure confirms the observations made above where structures with natural frequency of ωn/p = 8 show a behaviour that is dominated by rocking motion instead of elastic deformations. Therefore, the horizontal drift is controlled mainly by uplift peak rotation, which explains partly why different models have similar peak response predictions.",
    ),
    c(
        "fig16-limited-deformation",
        "Fig. 16",
        "The limited effects of clutched inerters on peak elastic deformations are also evident from Fig. 16.",
    ),
    c(
        "fig16-acceleration-most",
        "Fig. 16",
        "Moreover, the increased accelerations predicted by our mechanistic clutch model are also confirmed for most of the frequency ratios.",
    ),
    // §7
    c(
        "fig17-judder",
        "Fig. 17",
        "A mild juddering associated with the engagement-disengagement cycles described above is noticeable for a low value of kθ (Fig. 17a). Higher clutch stiffnesses result in a smoother engagement process at the macro scale …",
    ),
    c(
        "fig17-soft-delay",
        "Fig. 17",
        "… while softer clutches may cause a small delay in the disengagement at the very local level.",
    ),
    c(
        "fig18-not-determinant",
        "Fig. 18, §9",
        "However, for all practical purposes, the influence of the clutch stiffness is not determinant. This is demonstrated in Fig. 18 which presents the response spectra for flexible inerto-rocking structures with different clutch stiffness values.",
    ),
    c(
        "fig19-operational-immaterial",
        "Fig. 19",
        "It can be observed from Fig. 19 that operational levels of damping (i.e. ξ = 2%) are practically immaterial to the peak displacement or rotational response of flexible inerto-rocking structures.",
    ),
    c(
        "fig19-halves",
        "Fig. 19",
        "However, supplemental damping (i.e. ξ = 20%) is able to reduce significantly the base rotations (more than halving it for low frequency ratios in the order of ωg/p ≈ 5 …",
    ),
    c(
        "fig19-overturning-stiffer",
        "Fig. 19",
        "… and reduce the overturning for stiffer structures.",
    ),
    c(
        "fig19-deformation-less",
        "Fig. 19",
        "Similarly, reductions in peak elastic displacement demands are also observed for inerters with important damping levels, although the reductions are less dramatic than in the rotations.",
    ),
    c(
        "fig19-full-range",
        "Fig. 19",
        "These observations are valid for the full range of frequency ratios investigated.",
    ),
    c(
        "fig21-operational-negligible",
        "Fig. 21, §9",
        "In general, the effects of dissipating energy through friction are similar to those observed for viscous damping, with operational levels of dissipation resulting in negligible changes in the peak displacement and rotation responses.",
    ),
    c(
        "fig21-strong-reduces",
        "Fig. 21, §9",
        "Higher magnitude of dry friction can significantly reduce peak response for both elastic deformation and uplift rotation …",
    ),
    c(
        "fig21-eliminates-rocking",
        "Fig. 21",
        "… and can completely eliminate the rocking phase for high frequency excitations.",
    ),
    c(
        "fig22-first-engagement",
        "Fig. 22",
        "It can be noticed that upon first engagement, a strong discontinuity is introduced in the inverter's velocity leading to a large peak in the acceleration response.",
    ),
    c(
        "fig23-play-unnoticeable",
        "Fig. 23, §9",
        "It can be concluded from Fig. 23 that even these large values of gear play have an almost unnoticeable effect on peak deformations (displacements or rotations).",
    ),
    c(
        "s9-play-acceleration",
        "§9",
        "Contrastingly, the gear play did not have an appreciable effect on the base rotation and elastic deformation response, but it significantly increased the acceleration demands.",
    ),
    // §6–§7 and §9: the flexible structure's device, checks of their own (rows_clutch_settings)
    c(
        "fig15-conservation",
        "Fig. 15f",
        "This contrasts with the response depicted in Fig. 15f which maintains the conservation of energy throughout the motion of inerter.",
    ),
    c(
        "fig16-similar-peaks",
        "Fig. 16",
        "Therefore, the horizontal drift is controlled mainly by uplift peak rotation, which explains partly why different models have similar peak response predictions.",
    ),
    c(
        "s7-series-of-collisions",
        "§7.4, Fig. 22",
        "The consideration of gear play effectively introduces a series of collisions whenever the clutch engages.",
    ),
    c(
        "fig21-similar-to-viscous",
        "Fig. 21, §9",
        "In general, the effects of dissipating energy through friction are similar to those observed for viscous damping, …",
    ),
    c(
        "s9-damping-friction-more-significant",
        "§9",
        "Analyses conducted for a wide range of ground motion frequencies demonstrated that, for all practical purposes, the influence of the clutch stiffness is not determinant. Viscous damping and dry friction, on the other hand, were shown to have a more significant impact on the rotation and elastic deformation responses.",
    ),
    // §8
    c(
        "fig24-overturning",
        "Fig. 24",
        "Overall, Fig. 24 demonstrates the important reductions in the number of such overturning cases when the clutched inerter system is incorporated …",
    ),
    c(
        "fig24-dispersion",
        "Fig. 24",
        "Similarly, the noticeable reduction in the dispersion associated with clutched systems identified in previous studies is also evident.",
    ),
    c(
        "fig24-rotation-deformation",
        "Fig. 24",
        "The clutched inerter system leads to important reductions in base rotation but only mild elastic deformation mitigation.",
    ),
    c(
        "fig24-8pct",
        "Fig. 24, §9",
        "Interestingly, however, both the rotation and elastic displacement estimations of the clutch model advanced in this study are slightly lower (by around 8%) than the predictions made on the basis of the sequential engagement law adopted in previous studies. … This level of reductions is fairly constant throughout the frequency range under consideration.",
    ),
    c(
        "fig24-more-engagements",
        "Fig. 24",
        "This is attributed to the more faithful representation of the engagement process leading to a relatively larger number of inerter engagement events over the response history of the structure.",
    ),
    c(
        "fig24-acceleration-hardest",
        "Fig. 24",
        "These difficulties are also evidenced in Fig. 24, especially within the range of 12 < ωn < 18.",
    ),
    c(
        "fig24-mechanistic-acceleration",
        "Fig. 24",
        "Moreover, the mechanistic clutch model of the present study estimates higher acceleration levels than the sequential model of previous studies.",
    ),
    c(
        "fig24-el-centro",
        "Fig. 24",
        "In some cases, notably for the El Centro record, these peak accelerations may be even higher than those experienced in bare structures.",
    ),
    c(
        "s9-clutch-increases-acceleration",
        "§9",
        "Importantly, the mechanistic clutch model proposed in this paper predicts slightly lower rocking demands than the sequential model used in previous studies, while both formulations suggest that the incorporation of a clutch can increase the acceleration demands in flexible uplifting structures.",
    ),
];

/// The claim with this id (the rows name their own).
pub fn get(id: &str) -> &'static Claim {
    CLAIMS
        .iter()
        .find(|c| c.id == id)
        .unwrap_or_else(|| panic!("paper: claim {id} is not in the table"))
}
