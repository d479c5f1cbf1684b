!> Separation of a cohesionless material: the opening strain of `separation = true`.
!>
!> A granular material pulled apart does not resist until its grains touch again. The
!> Mohr-Coulomb and Drucker-Prager models keep, with `separation`, the plastic dilation of each
!> return that ends at the stress-free apex as an opening strain e_o >= 0 (a state value).
!> While e_o > 0 the particle carries no stress and any shear is plastic; volumetric
!> compression first closes the opening before the elastic response starts again. This is the
!> packed-density threshold of Dunatunga & Kamrin (2015, J. Fluid Mech. 779:483) written in
!> strains. Without it the dilation of every apex return is permanent, so a flow that passes
!> through tension repeatedly (the thin front of a collapse) gains volume at each pass.
module mpm_separation
    use mpm_kinds, only: wp
    implicit none
    private
    public :: close_opening, equivalent_shear

contains

    !> Start of a step of a separating material.
    !>
    !> With an opening e_o > 0 and a volumetric increment dv: if e_o + dv > 0 the particle
    !> stays open (e_o <- e_o + dv, the shear of the step is added to eps_q and `open` is
    !> true: the caller sets the stress to zero and returns); otherwise the step closes it and
    !> `de` keeps only the compression beyond closure (its volumetric part becomes e_o + dv).
    pure subroutine close_opening(de, opening, eps_q, open)
        real(wp), intent(inout) :: de(:)
            !! strain increment, tensor components (xx, yy, zz, xy[, yz, zx]) [-]
        real(wp), intent(inout) :: opening
            !! opening strain e_o [-]
        real(wp), intent(inout) :: eps_q
            !! accumulated equivalent plastic shear strain [-]
        logical, intent(out) :: open
            !! the particle stays open over the step

        real(wp) :: dvol

        open = .false.
        if (opening <= 0.0_wp) return
        dvol = de(1) + de(2) + de(3)
        if (opening + dvol > 0.0_wp) then
            opening = opening + dvol
            eps_q = eps_q + equivalent_shear(de)
            open = .true.
        else
            de(1:3) = de(1:3) + opening/3.0_wp
            opening = 0.0_wp
        end if
    end subroutine close_opening

    !> Equivalent shear strain sqrt(2/3 e : e) of the deviator e of a strain increment
    !> (tensor components xx, yy, zz, xy[, yz, zx]).
    pure real(wp) function equivalent_shear(de)
        real(wp), intent(in) :: de(:)
            !! strain increment [-]
        real(wp) :: mean
        mean = (de(1) + de(2) + de(3))/3.0_wp
        equivalent_shear = sqrt(2.0_wp/3.0_wp*(sum((de(1:3) - mean)**2) &
            + 2.0_wp*sum(de(4:)**2)))
    end function equivalent_shear

end module mpm_separation
