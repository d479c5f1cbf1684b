!> Stress and strain conventions, and the objective (Jaumann) rotation.
!>
!> Conventions, kept everywhere in mpm-geo:
!> - Cauchy stress, TENSION POSITIVE (compression negative, as in continuum mechanics).
!> - Voigt order xx yy zz xy yz zx; 2D (plane strain) stores xx yy zz xy (4 components).
!> - Strain increments are tensor components (eps_xy, not gamma_xy = 2 eps_xy).
!> - Spin increments are the independent components of Omega = W dt,
!>   W = (L - L^T)/2, L the velocity gradient: omega(1) = W_xy dt, omega(2) = W_yz dt,
!>   omega(3) = W_zx dt.
module mpm_stress
    use mpm_kinds, only: wp
    implicit none
    private
    public :: jaumann_rotation, add_jaumann_rotation, trace, double_contraction, voigt_matrix
    public :: isotropic_elastic_energy, mean_and_deviator

contains

    !> Rotation part of the Jaumann stress rate over a step: returns Omega sigma - sigma Omega.
    !>
    !> Added to the stress of the start of the step, it makes the update objective: a rigid
    !> rotation turns the stress with the body instead of creating it.
    pure function jaumann_rotation(stress, omega) result(dsig)
        real(wp), intent(in) :: stress(:)
            !! stress at the start of the step, 4 (2D) or 6 (3D) components [Pa]
        real(wp), intent(in) :: omega(3)
            !! spin increment W dt: xy, yz, zx components [-]
        real(wp) :: dsig(size(stress))
            !! stress increment from the rotation [Pa]

        real(wp) :: s(3, 3), w(3, 3), ws(3, 3)
        integer :: i, j

        if (size(stress) == 4) then
            dsig(1) = 2.0_wp*omega(1)*stress(4)
            dsig(2) = -2.0_wp*omega(1)*stress(4)
            dsig(3) = 0.0_wp
            dsig(4) = omega(1)*(stress(2) - stress(1))
            return
        end if
        s = voigt_matrix(stress(1:6))
        w = 0.0_wp
        w(1, 2) = omega(1)
        w(2, 1) = -omega(1)
        w(2, 3) = omega(2)
        w(3, 2) = -omega(2)
        w(3, 1) = omega(3)
        w(1, 3) = -omega(3)
        ! W S - S W = W S + (W S)^T for W antisymmetric and S symmetric
        do j = 1, 3
            do i = 1, 3
                ws(i, j) = w(i, 1)*s(1, j) + w(i, 2)*s(2, j) + w(i, 3)*s(3, j)
            end do
        end do
        dsig(1) = 2.0_wp*ws(1, 1)
        dsig(2) = 2.0_wp*ws(2, 2)
        dsig(3) = 2.0_wp*ws(3, 3)
        dsig(4) = ws(1, 2) + ws(2, 1)
        dsig(5) = ws(2, 3) + ws(3, 2)
        dsig(6) = ws(3, 1) + ws(1, 3)
    end function jaumann_rotation

    !> stress <- stress + (Omega sigma - sigma Omega), in place: the objective rotation of the
    !> stress over a step (jaumann_rotation without an array result, which would be a heap
    !> temporary in every stress update).
    pure subroutine add_jaumann_rotation(stress, omega)
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components [Pa]
        real(wp), intent(in) :: omega(3)
            !! spin increment W dt (xy, yz, zx) [-]

        real(wp) :: dsig(6)

        if (size(stress) == 4) then
            dsig(1) = 2.0_wp*omega(1)*stress(4)
            dsig(2) = -2.0_wp*omega(1)*stress(4)
            dsig(3) = 0.0_wp
            dsig(4) = omega(1)*(stress(2) - stress(1))
            stress(1:4) = stress(1:4) + dsig(1:4)
        else
            dsig = jaumann_rotation(stress(1:6), omega)
            stress(1:6) = stress(1:6) + dsig
        end if
    end subroutine add_jaumann_rotation

    !> The 3x3 matrix of a symmetric tensor in Voigt storage (xx yy zz xy yz zx), element by
    !> element (a reshape of a constructor is a library call, too slow per particle).
    pure function voigt_matrix(v) result(m)
        real(wp), intent(in) :: v(6)
            !! Voigt components
        real(wp) :: m(3, 3)

        m(1, 1) = v(1)
        m(2, 2) = v(2)
        m(3, 3) = v(3)
        m(1, 2) = v(4)
        m(2, 1) = v(4)
        m(2, 3) = v(5)
        m(3, 2) = v(5)
        m(3, 1) = v(6)
        m(1, 3) = v(6)
    end function voigt_matrix

    !> Trace of a symmetric tensor in Voigt storage.
    pure real(wp) function trace(t)
        real(wp), intent(in) :: t(:)
            !! 4 or 6 components
        trace = t(1) + t(2) + t(3)
    end function trace

    !> a : b for symmetric tensors in Voigt storage of tensor components.
    pure real(wp) function double_contraction(a, b)
        real(wp), intent(in) :: a(:)
            !! 4 or 6 components
        real(wp), intent(in) :: b(:)
            !! 4 or 6 components
        double_contraction = a(1)*b(1) + a(2)*b(2) + a(3)*b(3) &
            + 2.0_wp*sum(a(4:size(a))*b(4:size(b)))
    end function double_contraction

    !> Elastic energy per unit volume of a stress in an isotropic linear-elastic solid,
    !> 1/2 sigma : C^-1 : sigma = ((1 + nu) sigma : sigma - nu tr(sigma)^2) / (2 E) [J/m3].
    !> In plane strain the stored sigma_zz is part of sigma (and eps_zz = 0 follows from it).
    pure real(wp) function isotropic_elastic_energy(stress, young, poisson)
        real(wp), intent(in) :: stress(:)
            !! Cauchy stress, 4 or 6 components [Pa]
        real(wp), intent(in) :: young
            !! Young's modulus E [Pa]
        real(wp), intent(in) :: poisson
            !! Poisson's ratio nu [-]

        real(wp) :: tr

        tr = stress(1) + stress(2) + stress(3)
        isotropic_elastic_energy = ((1.0_wp + poisson)*double_contraction(stress, stress) &
            - poisson*tr*tr)/(2.0_wp*young)
    end function isotropic_elastic_energy

    !> Mean stress m = tr(sigma)/3, deviator s = sigma - m I and its radius sqrt(J2) =
    !> sqrt(s:s/2) of a stress.
    pure subroutine mean_and_deviator(stress, mean, dev, radius)
        real(wp), intent(in) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(out) :: mean
            !! mean stress m, tension positive [Pa]
        real(wp), intent(out) :: dev(:)
            !! deviator, as many components as stress [Pa]
        real(wp), intent(out) :: radius
            !! sqrt(J2) [Pa]

        mean = (stress(1) + stress(2) + stress(3))/3.0_wp
        dev = stress
        dev(1:3) = dev(1:3) - mean
        radius = sqrt(0.5_wp*double_contraction(dev, dev))
    end subroutine mean_and_deviator

end module mpm_stress
