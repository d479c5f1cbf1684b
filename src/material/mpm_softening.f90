!> Softening of strength parameters with the accumulated plastic shear strain, shared by the
!> elasto-plastic materials.
module mpm_softening
    use mpm_kinds, only: wp
    implicit none
    private
    public :: softening_weight, softened_strength
    public :: softening_none, softening_linear, softening_exponential, softening_names

    integer, parameter :: softening_none = 0         !! constant strength
    integer, parameter :: softening_linear = 1       !! linear from peak to residual
    integer, parameter :: softening_exponential = 2  !! exponential decay to residual
    character(len=*), parameter :: softening_names(0:2) = [character(len=11) :: "none", &
        "linear", "exponential"]
        !! names of the laws in the case file (`materials[i].softening.type`)

contains

    !> Fraction w of the way from the peak (0) to the residual value (1) of a strength
    !> parameter, x = x_peak + w (x_residual - x_peak):
    !> linear w = min(eps_q / eps_s, 1); exponential w = 1 - exp(-eps_q / eps_s); none w = 0.
    !> A non-positive eps_s means an immediate drop to the residual values at the first plastic
    !> strain.
    pure real(wp) function softening_weight(law, softening_strain, eps_q) result(w)
        integer, intent(in) :: law
            !! softening_none, softening_linear or softening_exponential
        real(wp), intent(in) :: softening_strain
            !! eps_s: strain at the residual (linear) or decay scale (exponential) [-]
        real(wp), intent(in) :: eps_q
            !! accumulated equivalent plastic shear strain [-]

        select case (law)
        case (softening_linear)
            if (softening_strain > 0.0_wp) then
                w = min(eps_q/softening_strain, 1.0_wp)
            else
                w = merge(1.0_wp, 0.0_wp, eps_q > 0.0_wp)
            end if
        case (softening_exponential)
            if (softening_strain > 0.0_wp) then
                ! exp(-700) ~ 1e-304: beyond that the decay is complete in double precision
                w = 1.0_wp - exp(-min(eps_q/softening_strain, 700.0_wp))
            else
                w = merge(1.0_wp, 0.0_wp, eps_q > 0.0_wp)
            end if
        case default
            w = 0.0_wp
        end select
    end function softening_weight

    !> Friction, cohesion and dilatancy after the plastic shear strain eps_q: each
    !> x = x_peak + w (x_residual - x_peak), w = softening_weight(law, softening_strain, eps_q).
    pure subroutine softened_strength(law, softening_strain, eps_q, peak, residual, friction, &
            cohesion, dilatancy)
        integer, intent(in) :: law
            !! softening_none, softening_linear or softening_exponential
        real(wp), intent(in) :: softening_strain
            !! eps_s [-]
        real(wp), intent(in) :: eps_q
            !! accumulated equivalent plastic shear strain [-]
        real(wp), intent(in) :: peak(3)
            !! peak friction angle [rad], cohesion [Pa], dilatancy angle [rad]
        real(wp), intent(in) :: residual(3)
            !! residual values, same order
        real(wp), intent(out) :: friction
            !! friction angle phi [rad]
        real(wp), intent(out) :: cohesion
            !! cohesion c [Pa]
        real(wp), intent(out) :: dilatancy
            !! dilatancy angle psi [rad]

        real(wp) :: w

        w = softening_weight(law, softening_strain, eps_q)
        friction = peak(1) + w*(residual(1) - peak(1))
        cohesion = peak(2) + w*(residual(2) - peak(2))
        dilatancy = peak(3) + w*(residual(3) - peak(3))
    end subroutine softened_strength

end module mpm_softening
